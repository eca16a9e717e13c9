#pragma once
/// @file The groove's cross-section (render/groove.hpp) and what shapes it along a curve: the
/// profile at a curve point (lip fillet, wall, floor fillet, floor) and its drop below the plate
/// top, solving its wall slope for its depth, the profiles' smoothing over a block of pixels,
/// averaging along a curve, the curl's lift, and the curve points the scan needs.

#include "render/fillet.hpp"
#include "render/groove.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

namespace crackle::render::groove {

/// A groove shallower than this share of the plate height (a tapering tip) fades out of the join:
/// its flat profile would otherwise stand in for a deeper groove beside it, out to its own reach.
constexpr double SHALLOW = 0.2;

inline double smooth01(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

/// The groove's cross-section at one curve point.
struct Profile {
    float floor = 0;         ///< m: half the flat floor's width (half the simulated opening less the floor fillet)
    float reach = 0;         ///< m: from the floor's edge to the plate top
    float fillet_top = 0;    ///< m
    float fillet_bottom = 0; ///< m
    float alpha = 0;         ///< rad: wall slope
    float depth = 0;         ///< m
    float share = 0;         ///< the groove's depth as a share of the local plate height (0..1)
    float age = 1;
    float gap = 0; ///< m: half the simulated opening (the crack's own width: the Mask's core)

    /// Drop below the plate top at distance d (m) from the curve. The lip fillet, the wall and the
    /// floor fillet meet where a solved profile's depth is the depth its slope reaches; a blend of
    /// profiles (where grooves meet, and the smoothing) is not solved, so the three are joined at
    /// the depth they reach together and scaled to the profile's depth: otherwise the floor fillet
    /// would start with a step (up to 0.7 mm on mud at 4096², along a line at a fixed distance).
    double drop(double d, const Fillets& f) const {
        const double x = floor + reach - d; // inward from the groove's outer edge
        if (x <= 0) return 0;
        if (x >= reach) return depth;
        const float slope = std::tan(alpha); // (float, as before: the maps stay the same)
        const double top_part = fillet_top * f.top(alpha, 1.0), wall = reach - fillet_top - fillet_bottom;
        const double reached = top_part + wall * slope + fillet_bottom * f.bottom(alpha, 1.0);
        const double scale = reached > 0 ? depth / reached : 0.0;
        if (x <= fillet_top) return scale * fillet_top * f.top(alpha, x / fillet_top);
        if (x <= reach - fillet_bottom) return scale * (top_part + (x - fillet_top) * slope);
        return scale * (reached - fillet_bottom * f.bottom(alpha, (reach - x) / fillet_bottom));
    }
};

inline Profile lerp(const Profile& a, const Profile& b, double t) {
    auto mix = [&](float p, float q) { return static_cast<float>((1 - t) * p + t * q); };
    return {mix(a.floor, b.floor),
            mix(a.reach, b.reach),
            mix(a.fillet_top, b.fillet_top),
            mix(a.fillet_bottom, b.fillet_bottom),
            mix(a.alpha, b.alpha),
            mix(a.depth, b.depth),
            mix(a.share, b.share),
            mix(a.age, b.age),
            mix(a.gap, b.gap)};
}

/// The profiles of a block of rows (and the rows of its halo), one channel per parameter and one
/// for the weight (1 where a pixel has a profile), smoothed together by three box passes of
/// PROFILE_SMOOTH_PX each way, wrapping in u; then divided by the smoothed weight.
class ProfileWindow {
public:
    ProfileWindow(int width, int rows)
        : m_width(width), m_rows(rows), m_data(std::size_t(width) * std::size_t(rows) * CH, 0.0f) {}
    void put(int x, int row, const Profile& p) {
        float* c = at(x, row);
        const std::array<float, CH> v{1.0f,    p.floor, p.reach, p.fillet_top, p.fillet_bottom,
                                      p.alpha, p.depth, p.share, p.age,        p.gap};
        std::copy(v.begin(), v.end(), c);
    }
    /// After smooth(): the pixel's profile, or none where no profile reached it.
    std::optional<Profile> profile(int x, int row) const {
        const float* c = at(x, row);
        if (c[0] <= 1e-6f) return std::nullopt;
        const float w = 1.0f / c[0];
        return Profile{c[1] * w, c[2] * w, c[3] * w, c[4] * w, c[5] * w, c[6] * w, c[7] * w, c[8] * w, c[9] * w};
    }
    /// Three box passes of `radius` each way (a 6·radius + 1 tap kernel, applied at once along the
    /// rows, wrapping, and down the columns; the window's edge rows only feed the halo, which is not
    /// kept).
    void smooth(int radius);

private:
    static constexpr std::size_t CH = 10;
    float* at(int x, int row) { return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH]; }
    const float* at(int x, int row) const {
        return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH];
    }
    int m_width, m_rows;
    std::vector<float> m_data;
};

/// The profile that reaches `depth` within `reach` with fillets `top`, `bottom`: α by regula falsi
/// (Illinois); a groove too narrow for its fillets or for MAX_WALL_DEG walls is widened.
Profile solve(Profile p, const Fillets& f);

/// Two passes of a moving average over `half` (in the units of `arc`) each way along a curve.
/// An open curve keeps its end values (the average runs over the values mirrored oddly about
/// each end, so the chains meeting at a junction still agree there); a closed one wraps.
std::vector<double> smooth_along(const std::vector<double>& arc, const std::vector<double>& values, double half,
                                 bool closed);

/// Curl lifts the rim as the post stage does (Fig. 4.11): by curl · (1 − d/reach)² (layer
/// heights) from the plate's edge (the floor's), concave, highest at the lip; the distance from
/// the floor's edge is eased over the floor fillet, so the lift meets the floor without a crease.
inline double curl_lift(double d, const Profile& p, const GrooveOptions& o) {
    const double fb = std::max(double(p.fillet_bottom), 1e-12);
    double from_lip = std::max(0.0, d - p.floor);
    from_lip = from_lip < fb ? from_lip * from_lip / (2 * fb) : from_lip - 0.5 * fb;
    return o.curl * sqr(std::max(0.0, 1.0 - from_lip / o.curl_reach));
}

/// The points of a curve the scan keeps (Douglas & Peucker 1973): curve smoothing and the wander
/// leave segments far below a pixel, and each costs a scan of the whole reach. A point is dropped
/// where the chord between its kept neighbours passes within `tolerance` pixels of it and the
/// profile interpolated along the chord (at the point's projection, as the scan interpolates) is
/// within `tolerance` pixels of its own, in height: shifts across the wall times its slope, depths in
/// pixels, the wall's angle by the height it moves (d tan α = dα / cos² α), the share by the depth it changes, the age
/// at 1/200 per `tolerance`; where the groove is shallow enough to fade out of the join, every point is kept.
std::vector<std::size_t> kept_points(const std::vector<Vec2>& at, const std::vector<Profile>& profile, double tolerance,
                                     double pixel, double top);

} // namespace crackle::render::groove
