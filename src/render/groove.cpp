#include "render/groove.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "render/fillet.hpp"
#include "render/groove_scan.hpp"
#include "render/relief.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace crackle::render {

namespace {

/// Rows scanned and joined together: the halo's rows (HALO each side) are scanned twice, 9 % more
/// work at 64 rows, 5 % at 128.
constexpr int BLOCK_ROWS = 128;
constexpr double PROFILE_BLEND = 4.0;
/// Beyond its groove's extent a curve fades out of the join over this share of the extent.
constexpr double FADE = 0.4;
/// A groove shallower than this share of the plate height (a tapering tip) fades out of the join:
/// its flat profile would otherwise stand in for a deeper groove beside it, out to its own reach.
constexpr double SHALLOW = 0.2;
/// The steepest turn of a groove's slope between neighbouring pixels anywhere on a fillet:
/// narrower features would show as creases (the bound is 10° between neighbours).
constexpr double TURN_PER_PIXEL = 9.0 * PI / 180.0;
/// The profiles' parameters are smoothed over about this many pixels: a pixel's nearest point of a
/// curve jumps across the inner side of a bend (and its nearest curves change where they meet),
/// and the profile with it.
constexpr int PROFILE_SMOOTH_PX = 1;
/// Rows of a block's halo: the reach of the profiles' smoothing.
constexpr int HALO = 3 * PROFILE_SMOOTH_PX;

double smooth01(double x) {
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
        const double top_part = fillet_top * f.top(alpha, 1.0), wall = reach - fillet_top - fillet_bottom;
        const double reached = top_part + wall * std::tan(alpha) + fillet_bottom * f.bottom(alpha, 1.0);
        const double scale = reached > 0 ? depth / reached : 0.0;
        if (x <= fillet_top) return scale * fillet_top * f.top(alpha, x / fillet_top);
        if (x <= reach - fillet_bottom) return scale * (top_part + (x - fillet_top) * std::tan(alpha));
        return scale * (reached - fillet_bottom * f.bottom(alpha, (reach - x) / fillet_bottom));
    }
};

Profile lerp(const Profile& a, const Profile& b, double t) {
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
    void smooth(int radius) {
        std::vector<float> kernel{1.0f};
        for (int pass = 0; pass < 3; ++pass) {
            std::vector<float> wider(kernel.size() + 2 * std::size_t(radius), 0.0f);
            for (std::size_t k = 0; k < kernel.size(); ++k)
                for (std::size_t j = 0; j <= 2 * std::size_t(radius); ++j)
                    wider[k + j] += kernel[k] / float(2 * radius + 1);
            kernel = std::move(wider);
        }
        const std::size_t reach = kernel.size() / 2, n = std::size_t(m_width) * CH, rows = std::size_t(m_rows);
        // Along the rows: each row padded by its wrapped ends.
        std::vector<float> line(n + 2 * reach * CH);
        for (std::size_t row = 0; row < rows; ++row) {
            float* data = &m_data[row * n];
            const std::size_t width = std::size_t(m_width);
            for (std::size_t p = 0; p < width + 2 * reach; ++p) // pixel p − reach, wrapped
                std::copy_n(data + ((p + width * reach - reach) % width) * CH, CH, &line[p * CH]);
            std::fill_n(data, n, 0.0f);
            for (std::size_t j = 0; j < kernel.size(); ++j) {
                const float k = kernel[j], *in = &line[j * CH];
                for (std::size_t i = 0; i < n; ++i)
                    data[i] += k * in[i];
            }
        }
        // Down the columns: the rows as they were before they were overwritten, in a ring.
        const std::size_t kept = kernel.size();
        std::vector<float> before(kept * n);
        for (std::size_t row = 0; row < rows; ++row) {
            float* data = &m_data[row * n];
            std::copy_n(data, n, &before[(row % kept) * n]);
            std::fill_n(data, n, 0.0f);
            for (std::size_t j = 0; j < kernel.size(); ++j) {
                const std::size_t from = row + j; // + reach − reach: row − reach + j, if within the window
                if (from < reach || from - reach >= rows) continue;
                const std::size_t source = from - reach;
                const float k = kernel[j];
                const float* in = source <= row ? &before[(source % kept) * n] : &m_data[source * n];
                for (std::size_t i = 0; i < n; ++i)
                    data[i] += k * in[i];
            }
        }
    }

private:
    static constexpr std::size_t CH = 10;
    float* at(int x, int row) { return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH]; }
    const float* at(int x, int row) const {
        return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH];
    }
    int m_width, m_rows;
    std::vector<float> m_data;
};

/// The profile that reaches `depth` within `reach` with fillets `top`, `bottom`: α by bisection;
/// a groove too narrow for its fillets or for MAX_WALL_DEG walls is widened.
Profile solve(Profile p, const Fillets& f) {
    const double max_alpha = MAX_WALL_DEG * PI / 180.0;
    p.reach = std::max(p.reach, p.fillet_top + p.fillet_bottom);
    auto depth_at = [&](double alpha) {
        return p.fillet_top * f.top(alpha, 1.0) + p.fillet_bottom * f.bottom(alpha, 1.0)
               + (p.reach - p.fillet_top - p.fillet_bottom) * std::tan(alpha);
    };
    if (p.depth <= 0) {
        p.alpha = 0;
        return p;
    }
    if (depth_at(max_alpha) < p.depth) {
        p.alpha = static_cast<float>(max_alpha);
        const double fillet_depth = p.fillet_top * f.top(max_alpha, 1.0) + p.fillet_bottom * f.bottom(max_alpha, 1.0);
        p.reach = static_cast<float>(p.fillet_top + p.fillet_bottom + (p.depth - fillet_depth) / std::tan(max_alpha));
        return p;
    }
    // The depth grows monotonically with α: the Illinois variant of regula falsi (Dowell & Jarratt
    // 1971) to a depth within 1e-12 of it, in about 8 evaluations where bisection took 40.
    double lo = 0, hi = max_alpha, f_lo = -p.depth, f_hi = depth_at(hi) - p.depth, alpha = hi;
    for (int k = 0, side = 0; k < 100; ++k) {
        alpha = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if (!(alpha > lo && alpha < hi)) alpha = 0.5 * (lo + hi);
        const double miss = depth_at(alpha) - p.depth;
        if (std::abs(miss) <= 1e-12 * p.depth || hi - lo <= 1e-15) break;
        if (miss < 0) {
            lo = alpha, f_lo = miss;
            if (side < 0) f_hi *= 0.5;
            side = -1;
        } else {
            hi = alpha, f_hi = miss;
            if (side > 0) f_lo *= 0.5;
            side = 1;
        }
    }
    p.alpha = static_cast<float>(alpha);
    // The table's interpolation: the depth the profile reaches is the depth at this α.
    p.depth = static_cast<float>(depth_at(p.alpha));
    return p;
}

/// The curves' distances joined by a smooth minimum, −r·ln Σ exp(−dᵢ/r) (symmetric in the
/// curves, so the join does not depend on their order, and smooth), and their profiles blended
/// with the weights exp(−dᵢ/r) / Σ: where two cracks meet, the plate's corner is rounded in plan
/// by about r, and the ridge between two grooves has a rounded crest, with no crease along the
/// line of equal distance. A curve nearer than the others by several r keeps its own distance
/// and profile.
template <class ProfileOf, class ExtentOf>
std::pair<double, Profile> join_nearest(const scan::Nearest& n, double r, ProfileOf&& profile_of,
                                        ExtentOf&& extent_of) {
    // Each curve's terms fade out beyond its groove's extent (over FADE of it), so a curve
    // leaves the join smoothly where its scan ends and never bends its own groove. The profiles blend over a longer
    // distance than the distances join (PROFILE_BLEND × r): a later, shallower crack's floor meets the deeper one it
    // ends on by a gentle step.
    std::array<double, scan::Nearest::SLOTS> fade{}, w{};
    std::array<Profile, scan::Nearest::SLOTS> profile;
    // The nearest of the curves that take part: a faded-out curve nearer than them must not be
    // the reference of the exponentials (their terms would underflow beyond ~28 r, and the
    // grooves vanish along the edge of its scan).
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < scan::Nearest::SLOTS; ++k) {
        if (n.curve[k] < 0) continue;
        const double beyond_extent = smooth01((n.distance[k] / std::max(extent_of(k), 1e-12) - 1.0) / FADE);
        if (beyond_extent >= 1.0) continue; // faded out: its profile is not needed
        profile[k] = profile_of(k);
        fade[k] = (1.0 - beyond_extent) * smooth01(profile[k].share / SHALLOW);
        if (fade[k] > 0) least = std::min(least, double(n.distance[k]));
    }
    if (!std::isfinite(least)) return {std::numeric_limits<double>::infinity(), Profile{}};
    double sum = 0;
    for (int k = 0; k < scan::Nearest::SLOTS; ++k) {
        if (fade[k] <= 0) continue;
        const double beyond = n.distance[k] - least; // exp(−0) = 1 exactly: the nearest curve's terms
        sum += fade[k] * (beyond > 0 ? std::exp(-beyond / r) : 1.0);
        w[k] = fade[k] * (beyond > 0 ? std::exp(-beyond / (PROFILE_BLEND * r)) : 1.0);
    }
    Profile p;
    double seen = 0;
    for (int k = 0; k < scan::Nearest::SLOTS; ++k) {
        if (w[k] <= 0) continue;
        p = seen == 0 ? profile[k] : lerp(p, profile[k], w[k] / (seen + w[k]));
        seen += w[k];
    }
    return {std::max(least - r * (sum == 1.0 ? 0.0 : std::log(sum)), 0.0), p}; // ln 1 = 0 exactly: one curve
}

/// Two passes of a moving average over `half` (in the units of `arc`) each way along a curve.
/// An open curve keeps its end values (the average runs over the values mirrored oddly about
/// each end, so the chains meeting at a junction still agree there); a closed one wraps.
std::vector<double> smooth_along(const std::vector<double>& arc, const std::vector<double>& values, double half,
                                 bool closed) {
    const std::size_t n = values.size();
    if (n < 3 || half <= 0) return values;
    const double length = arc.back(), margin = 2 * half;
    std::vector<double> s, v;
    for (std::size_t k = n - 1; k-- > 1;) { // before the start, in order of arc length
        const std::size_t j = closed ? n - 1 - k : k;
        if (closed && length - arc[j] <= margin) s.push_back(arc[j] - length), v.push_back(values[j]);
        if (!closed && arc[j] <= margin) s.push_back(-arc[j]), v.push_back(2 * values[0] - values[j]);
    }
    const std::size_t first = s.size();
    s.insert(s.end(), arc.begin(), arc.end());
    v.insert(v.end(), values.begin(), values.end());
    for (std::size_t k = n - 1; k-- > 1;) { // after the end
        const std::size_t j = closed ? n - 1 - k : k;
        if (closed && arc[j] <= margin) s.push_back(length + arc[j]), v.push_back(values[j]);
        if (!closed && length - arc[j] <= margin)
            s.push_back(2 * length - arc[j]), v.push_back(2 * values[n - 1] - values[j]);
    }
    const std::size_t m = s.size();
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double> sum(m + 1, 0.0), mean(m);
        for (std::size_t i = 0; i < m; ++i)
            sum[i + 1] = sum[i] + v[i];
        for (std::size_t i = 0, lo = 0, hi = 0; i < m; ++i) {
            while (s[i] - s[lo] > half)
                ++lo;
            hi = std::max(hi, i);
            while (hi + 1 < m && s[hi + 1] - s[i] <= half)
                ++hi;
            mean[i] = (sum[hi + 1] - sum[lo]) / double(hi + 1 - lo);
        }
        v = std::move(mean);
    }
    std::vector<double> out(v.begin() + static_cast<std::ptrdiff_t>(first),
                            v.begin() + static_cast<std::ptrdiff_t>(first + n));
    if (!closed) out.front() = values.front(), out.back() = values.back();
    return out;
}

/// A block of rows' joined distances and smoothed profiles (over the block and its halo).
struct Joined {
    int r0, r1, h0;
    std::vector<float> distance;
    ProfileWindow window;
};

/// Each segment's profiles at its two ends and its extent (as a float), side by side: the join
/// reads them for every pixel, and one place is cheaper than three.
struct SegmentEnds {
    Profile a, b;
    float extent = 0;
};

std::vector<SegmentEnds> segment_ends(const std::vector<scan::Segment>& segs,
                                      const std::vector<std::vector<Profile>>& profiles) {
    std::vector<SegmentEnds> ends(segs.size());
    for (std::size_t k = 0; k < segs.size(); ++k)
        ends[k] = {profiles[segs[k].curve][segs[k].point], profiles[segs[k].curve][segs[k].point + 1],
                   static_cast<float>(segs[k].extent)};
    return ends;
}

Joined join_block(const PixelGrid& g, const std::vector<scan::Segment>& segs, const scan::Bin& bin, int block,
                  const std::vector<SegmentEnds>& ends, const GrooveOptions& o) {
    const int W = g.width, r0 = block * BLOCK_ROWS, r1 = std::min(g.height, r0 + BLOCK_ROWS), h0 = r0 - HALO,
              rows = r1 - r0 + 2 * HALO;
    std::vector<scan::Nearest> state(static_cast<std::size_t>(rows * W));
    scan::offer_block(g, segs, bin, h0, rows, o.wedge_margin_px, state);
    // Where grooves meet, their distances join smoothly (join_nearest); the profiles are smoothed
    // over the block and its halo.
    Joined j{r0, r1, h0, std::vector<float>(state.size(), std::numeric_limits<float>::infinity()),
             ProfileWindow(W, rows)};
    for (int row = 0; row < rows; ++row)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = static_cast<std::size_t>(row * W + x);
            const scan::Nearest& n = state[i];
            if (n.empty()) continue;
            const auto [d, p] = join_nearest(
                n, o.join_radius,
                [&](int slot) {
                    const SegmentEnds& e = ends[n.segment[static_cast<std::size_t>(slot)]];
                    return lerp(e.a, e.b, n.t[static_cast<std::size_t>(slot)]);
                },
                [&](int slot) { return double(ends[n.segment[static_cast<std::size_t>(slot)]].extent); });
            if (!std::isfinite(d)) continue;
            j.distance[i] = static_cast<float>(d);
            j.window.put(x, row, p);
        }
    j.window.smooth(PROFILE_SMOOTH_PX);
    return j;
}

/// Curl lifts the rim as the post stage does (Fig. 4.11): by curl · (1 − d/reach)² (layer
/// heights) from the plate's edge (the floor's), concave, highest at the lip; the distance from
/// the floor's edge is eased over the floor fillet, so the lift meets the floor without a crease.
double curl_lift(double d, const Profile& p, const GrooveOptions& o) {
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
                                     double pixel, double top) {
    const std::size_t n = at.size();
    std::vector<std::size_t> kept;
    if (n < 3 || tolerance <= 0) {
        for (std::size_t i = 0; i < n; ++i)
            kept.push_back(i);
        return kept;
    }
    auto extent = [&](std::size_t i) { return double(profile[i].floor + profile[i].reach); };
    auto error = [&](std::size_t i, std::size_t j, std::size_t m) {
        const Vec2 chord = at[j] - at[i];
        const double l2 = chord.squaredNorm();
        const double t = l2 > 0 ? std::clamp((at[m] - at[i]).dot(chord) / l2, 0.0, 1.0) : 0.0;
        const Profile& p = profile[m];
        const Profile q = lerp(profile[i], profile[j], t);
        // A wall of slope tan α turns a shift across it into α's tangent times that in height.
        const double reach = std::max(p.reach, q.reach) / pixel, wall = std::max(1.0, std::tan(double(p.alpha)));
        return std::max(
            {wall * (at[i] + t * chord - at[m]).norm(), wall * std::abs(p.floor - q.floor) / pixel,
             wall * std::abs(p.reach - q.reach) / pixel, wall * std::abs(p.fillet_top - q.fillet_top) / pixel,
             wall * std::abs(p.fillet_bottom - q.fillet_bottom) / pixel, std::abs(p.depth - q.depth) / pixel,
             std::abs(p.gap - q.gap) / pixel, std::abs(p.alpha - q.alpha) * reach * (1 + wall * wall),
             std::abs(p.share - q.share) * top / pixel, std::abs(p.age - q.age) * 200 * tolerance,
             // a segment's extent (where its curve fades out of the join) is its ends' larger
             std::abs(std::max(extent(i), extent(j)) - extent(m)) / pixel});
    };
    // Where a groove fades out of the join (a tapering tip), its share moves the joined distance by
    // up to r / fade: those points are all kept, and the runs between them simplified.
    std::vector<std::uint8_t> keep(n, 0);
    keep.front() = keep.back() = 1;
    for (std::size_t i = 0; i < n; ++i)
        keep[i] = keep[i] || profile[i].share < SHALLOW;
    std::vector<std::pair<std::size_t, std::size_t>> spans;
    for (std::size_t i = 0, last = 0; i < n; ++i)
        if (i > 0 && keep[i]) {
            if (i - last > 1) spans.emplace_back(last, i);
            last = i;
        }
    while (!spans.empty()) {
        const auto [i, j] = spans.back();
        spans.pop_back();
        double worst = 0;
        std::size_t split = i;
        for (std::size_t m = i + 1; m < j; ++m)
            if (const double e = error(i, j, m); e > worst) worst = e, split = m;
        if (worst <= tolerance) continue;
        keep[split] = 1;
        spans.emplace_back(i, split);
        spans.emplace_back(split, j);
    }
    for (std::size_t i = 0; i < n; ++i)
        if (keep[i]) kept.push_back(i);
    return kept;
}

} // namespace

GrooveField groove_field(const PixelGrid& g, const std::vector<CrackCurve>& curves, const std::vector<float>& top,
                         const GrooveOptions& o) {
    const std::size_t px = g.pixels();
    GrooveField out;
    out.drop.assign(px, 0.0f);
    out.lift.assign(px, 0.0f);
    out.coverage.assign(px, 0.0f);
    out.age.assign(px, 1.0f);
    out.distance.assign(px, std::numeric_limits<float>::infinity());
    const int W = g.width, H = g.height;
    auto to_px = [&](const Vec2& uv) { return Vec2(uv.x() * W - 0.5, (1.0 - uv.y()) * H - 0.5); };
    auto top_at = [&](const Vec2& p) {
        const int x = ((static_cast<int>(std::lround(p.x())) % W) + W) % W;
        int y = static_cast<int>(std::lround(p.y()));
        y = g.wrap_v ? ((y % H) + H) % H : std::clamp(y, 0, H - 1);
        return double(top[g.index(x, y)]);
    };

    // === Profiles at the curves' points, and the segments to scan. The lip fillet spans the
    // reach (the slope grows all the way to the floor fillet, as the raster grooves' t² and
    // circle profiles do); the shape sets how late it steepens.
    const double top_exponent = 1.0 + 3.0 * o.crack_shape;
    const double floor_lift = 1.0 + (o.curl > 0 && o.curl_reach > 0 ? o.curl : 0.0);
    const Fillets fillets{FilletTable(top_exponent), FilletTable(1.0, floor_lift), floor_lift};
    // The fillets' fastest turns, in α per fillet length.
    const double top_rate = fillets.top.steepest_turn(), bottom_rate = fillets.bottom.steepest_turn();
    const double shape_pixel = o.shape_pixel > 0 ? o.shape_pixel : o.pixel;
    // === The curl's lift reaches a few layer heights from the lip, far beyond most grooves, and
    // varies there on the scale of the reach and of the join's rounding: it is measured on a grid
    // coarser by k (its step at most a third of the join radius) and interpolated bicubically.
    const bool curl = o.curl > 0 && o.curl_reach > 0;
    // On the sphere's map (rows of shrinking width) the coarser grid was 2.9 % of the lift and 4°
    // (99th percentile of the normals) off in the tests: there the lift is measured at every pixel.
    int k = o.lift_step_px;
    if (k <= 0)
        for (k = 1;
             g.wrap_v && 2 * k * o.pixel <= o.join_radius / 3.0 * (1 + 1e-9) && W % (2 * k) == 0 && H % (2 * k) == 0;)
            k *= 2;
    CRACKLE_ASSERT(W % k == 0 && H % k == 0, "the lift's step " << k << " does not divide the map");
    std::vector<std::vector<Profile>> profiles(curves.size()), coarse_profiles(curves.size());
    std::vector<CrackCurve> reduced(curves.size()), coarse_reduced(curves.size());
    parallel_tasks(static_cast<int>(curves.size()), [&](int curve) {
        const auto c = static_cast<std::size_t>(curve);
        const CrackCurve& cv = curves[c];
        const std::size_t n = cv.uv.size();
        profiles[c].resize(n);
        // The plates' height, the opening and the weight along the curve, averaged over about
        // a third of an element each way: the profile (its floor, reach and wall slope) changes
        // smoothly along the crack; its depth is a share of the plate height at each pixel
        // (below), so the walls carry no steps where the sampled height does.
        std::vector<double> top_here(n), opening(n), weight(n), arc(n, 0.0);
        for (std::size_t i = 0; i < n; ++i) {
            top_here[i] = top_at(to_px(cv.uv[i]));
            opening[i] = cv.opening[i];
            weight[i] = cv.weight[i];
            if (i > 0) arc[i] = arc[i - 1] + (to_px(cv.uv[i]) - to_px(cv.uv[i - 1])).norm();
        }
        for (std::vector<double>* values : {&top_here, &opening, &weight})
            *values = smooth_along(arc, *values, o.smoothing_px, cv.closed);
        std::vector<Vec2> at(n);
        for (std::size_t i = 0; i < n; ++i)
            at[i] = to_px(cv.uv[i]);
        const double max_top = n > 0 ? *std::max_element(top_here.begin(), top_here.end()) : 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const double taper = cv.taper[i], w = weight[i];
            Profile p;
            double share = std::min(1.0, o.crack_depth * std::sqrt(w));
            if (o.crack_depth <= 0) {
                // bake.crack_depth = 0 leaves the depth to the simulation: a closed crack is cut
                // by the bevel only, one that post.shrinkage opened goes through the layer to the
                // ground, as the raster bake's gaps do (table-5-2-*).
                const double bevel = top_here[i] > 0 ? std::min(1.0, o.bevel / top_here[i]) : 0.0;
                share = bevel + (1.0 - bevel) * smooth01(opening[i] / o.pixel);
            }
            p.share = static_cast<float>(share * taper);
            p.floor = static_cast<float>(0.5 * opening[i] * taper);
            // A crack closes at its tip: the floor narrows over its groove's own width (its
            // extent), so the walls meet at the tip in a rounded point, not a crease.
            const double from_tip = std::min(cv.tip_front ? arc[i] : 1e300, cv.tip_back ? arc.back() - arc[i] : 1e300);
            if (from_tip < 1e300) {
                const double extent_px = (p.floor + std::max(o.rounding, o.crack_width * w)) / o.pixel;
                p.floor = static_cast<float>(p.floor * smooth01(from_tip / std::max(extent_px, 1.0)));
            }
            p.depth = static_cast<float>(top_here[i] * p.share);
            p.reach = static_cast<float>(std::max(o.rounding, o.crack_width * w) * std::max(taper, 0.15));
            p.age = cv.age[i];
            // The fillets are long enough that the slope turns by at most TURN_PER_PIXEL per shape
            // pixel (bake.shape_size) at the fillet's fastest. The wall's angle is known after a
            // solve, and longer fillets make it gentler: from the steepest wall's, the fillets
            // only lengthen, so the last profile's turns are within what its fillets were sized for.
            Profile solved;
            double least = 0, least_floor = 0;
            for (int pass = 0; pass < 4; ++pass) {
                const double wall = pass == 0 ? MAX_WALL_DEG * PI / 180.0 : double(solved.alpha);
                least = std::max(least, wall / TURN_PER_PIXEL * shape_pixel);
                least_floor = std::max(least_floor, fillets.shown(wall) / TURN_PER_PIXEL * shape_pixel);
                p.fillet_bottom = static_cast<float>(std::max(o.rounding, least_floor * bottom_rate));
                p.fillet_top =
                    static_cast<float>(std::max({o.rounding, least * top_rate, double(p.reach - p.fillet_bottom)}));
                solved = solve(p, fillets);
            }
            // The simulated opening is the gap between the plates' lips: the floor fillets (the
            // walls' feet) stand inside it, so the trough is the opening plus the walls and lip
            // fillets (with a floor as wide as the opening and the floor fillets beside it, mud's
            // plates read as pebbles on a bed of dirt). The Mask's core stays the whole gap.
            solved.gap = solved.floor;
            solved.floor = std::max(0.0f, solved.floor - solved.fillet_bottom);
            profiles[c][i] = solved;
        }
        // Only the points the scans need: the rest lie within o.simplify_px of the chords, in the
        // pixels of the grid scanned.
        auto reduce = [&](double step, CrackCurve& r, std::vector<Profile>& own) {
            r.closed = cv.closed;
            for (std::size_t i : kept_points(at, profiles[c], o.simplify_px * step, o.pixel * step, max_top))
                r.uv.push_back(cv.uv[i]), own.push_back(profiles[c][i]);
        };
        if (curl) reduce(k, coarse_reduced[c], coarse_profiles[c]);
        std::vector<Profile> own;
        reduce(1, reduced[c], own);
        profiles[c] = std::move(own);
    });

    // === The grooves: each pixel's distance to the curves within their grooves' extent, joined
    // where grooves meet, and the profile there.
    auto extents = [&](const std::vector<std::vector<Profile>>& of, double beyond) {
        std::vector<std::vector<double>> e(curves.size());
        for (std::size_t c = 0; c < curves.size(); ++c)
            for (const Profile& p : of[c])
                e[c].push_back(p.floor + std::max(double(p.reach), beyond));
        return e;
    };
    // Within the groove, the lift is shaped by the groove's own distance; from half its extent
    // outwards it blends into the lift field (below), which reaches farther at a coarser step.
    std::vector<float> own_lift(curl ? px : 0, 0.0f);
    Timer timer;
    {
        const std::vector<scan::Segment> segs = scan::segments(g, reduced, extents(profiles, 0.0), FADE);
        const std::vector<scan::Bin> bins = scan::bins(g, segs, BLOCK_ROWS, HALO);
        const std::vector<SegmentEnds> ends = segment_ends(segs, profiles);
        parallel_tasks(static_cast<int>(bins.size()), [&](int block) {
            const Joined j = join_block(g, segs, bins[static_cast<std::size_t>(block)], block, ends, o);
            for (int y = j.r0; y < j.r1; ++y) {
                const double pixel = std::min(g.metres_u[static_cast<std::size_t>(y)], g.metres_v);
                for (int x = 0; x < W; ++x) {
                    const double d = j.distance[static_cast<std::size_t>((y - j.h0) * W + x)];
                    const std::optional<Profile> found = j.window.profile(x, y - j.h0);
                    if (!std::isfinite(d) || !found) continue;
                    const Profile& p = *found;
                    const std::size_t i = g.index(x, y);
                    const double share = p.depth > 0 ? p.share * p.drop(d, fillets) / p.depth : 0.0;
                    const double half = std::max(double(p.gap), 0.5 * pixel);
                    out.drop[i] = static_cast<float>(top[i] * std::clamp(share, 0.0, 1.0));
                    out.coverage[i] = static_cast<float>(std::clamp((half - d) / pixel + 0.5, 0.0, 1.0));
                    out.age[i] = p.age;
                    out.distance[i] = static_cast<float>(d);
                    if (curl) {
                        const double extent = p.floor + p.reach;
                        out.lift[i] = static_cast<float>(top[i] * curl_lift(d, p, o));
                        own_lift[i] = static_cast<float>(1.0 - smooth01((d - 0.5 * extent) / (0.5 * extent)));
                    }
                }
            }
        });
    }
    const double t_grooves = timer.seconds();
    if (!curl) return out;

    PixelGrid coarse;
    coarse.width = W / k;
    coarse.height = H / k;
    coarse.wrap_v = g.wrap_v;
    coarse.metres_v = g.metres_v * k;
    for (int y = 0; y < coarse.height; ++y) // the rows' metres at the coarse row's middle
        coarse.metres_u.push_back(k * 0.5
                                  * (g.metres_u[static_cast<std::size_t>(k * y + (k - 1) / 2)]
                                     + g.metres_u[static_cast<std::size_t>(k * y + k / 2)]));
    std::vector<float> lift(coarse.pixels(), 0.0f);
    {
        const std::vector<scan::Segment> segs =
            scan::segments(coarse, coarse_reduced, extents(coarse_profiles, o.curl_reach), FADE);
        const std::vector<scan::Bin> bins = scan::bins(coarse, segs, BLOCK_ROWS, HALO);
        const std::vector<SegmentEnds> ends = segment_ends(segs, coarse_profiles);
        parallel_tasks(static_cast<int>(bins.size()), [&](int block) {
            const Joined j = join_block(coarse, segs, bins[static_cast<std::size_t>(block)], block, ends, o);
            for (int y = j.r0; y < j.r1; ++y)
                for (int x = 0; x < coarse.width; ++x) {
                    const double d = j.distance[static_cast<std::size_t>((y - j.h0) * coarse.width + x)];
                    const std::optional<Profile> found = j.window.profile(x, y - j.h0);
                    if (std::isfinite(d) && found)
                        lift[coarse.index(x, y)] = static_cast<float>(curl_lift(d, *found, o));
                }
        });
    }
    const double t_lift = timer.seconds();
    const std::vector<float> fine = upsample_cubic(coarse, lift, k);
    parallel_rows(H, [&](int y) {
        for (int x = 0; x < W; ++x) {
            const std::size_t i = g.index(x, y);
            const double far = top[i] * std::clamp(double(fine[i]), 0.0, o.curl);
            out.lift[i] = static_cast<float>(own_lift[i] * out.lift[i] + (1.0 - own_lift[i]) * far);
        }
    });
    log::debug("grooves: ", t_grooves, " s; the curl's lift on a grid ", k, " px apart ", t_lift - t_grooves,
               " s, interpolated ", timer.seconds() - t_lift, " s");
    return out;
}

} // namespace crackle::render
