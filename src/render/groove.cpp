#include "render/groove.hpp"

#include "core/parallel.hpp"
#include "render/fillet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace crackle::render {

namespace {

constexpr int BLOCK_ROWS = 64;
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

    /// Drop below the plate top at distance d (m) from the curve.
    double drop(double d, const Fillets& f) const {
        const double x = floor + reach - d; // inward from the groove's outer edge
        if (x <= 0) return 0;
        if (x >= reach) return depth;
        if (x <= fillet_top) return fillet_top * f.top(alpha, x / fillet_top);
        const double top_part = fillet_top * f.top(alpha, 1.0);
        if (x <= reach - fillet_bottom) return top_part + (x - fillet_top) * std::tan(alpha);
        return depth - fillet_bottom * f.bottom(alpha, (reach - x) / fillet_bottom);
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
    void smooth(int radius) {
        std::vector<double> sum(CH);
        std::vector<float> line;
        for (int pass = 0; pass < 3; ++pass) {
            // Along the rows (wrapping), then along the columns (the window's edge rows only feed
            // the halo, which is not kept).
            for (int row = 0; row < m_rows; ++row)
                box(at(0, row), m_width, CH, radius, true, sum, line);
            for (int x = 0; x < m_width; ++x)
                box(at(x, 0), m_rows, std::size_t(m_width) * CH, radius, false, sum, line);
        }
    }

private:
    static constexpr std::size_t CH = 10;
    float* at(int x, int row) { return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH]; }
    const float* at(int x, int row) const {
        return &m_data[(std::size_t(row) * std::size_t(m_width) + std::size_t(x)) * CH];
    }
    /// The mean over 2·radius + 1 elements of each channel, `n` elements `stride` floats apart
    /// (wrapping, or zero past the ends).
    static void box(float* first, int n, std::size_t stride, int radius, bool wrap, std::vector<double>& sum,
                    std::vector<float>& line) {
        const auto r = static_cast<std::size_t>(radius), count = static_cast<std::size_t>(n);
        line.assign((count + 2 * r) * CH, 0.0f);
        for (std::size_t k = 0; k < count; ++k)
            std::copy_n(first + k * stride, CH, &line[(k + r) * CH]);
        if (wrap)
            for (std::size_t k = 0; k < r; ++k) {
                std::copy_n(&line[(count + k) * CH], CH, &line[k * CH]);           // before: the last r
                std::copy_n(&line[(r + k) * CH], CH, &line[(count + r + k) * CH]); // after: the first r
            }
        std::fill(sum.begin(), sum.end(), 0.0);
        for (std::size_t k = 0; k < 2 * r; ++k)
            for (std::size_t c = 0; c < CH; ++c)
                sum[c] += line[k * CH + c];
        const double inv = 1.0 / double(2 * r + 1);
        for (std::size_t k = 0; k < count; ++k) {
            const float *in = &line[(k + 2 * r) * CH], *gone = &line[k * CH];
            float* out = first + k * stride;
            for (std::size_t c = 0; c < CH; ++c) {
                sum[c] += in[c];
                out[c] = static_cast<float>(sum[c] * inv);
                sum[c] -= gone[c];
            }
        }
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
    double lo = 0, hi = max_alpha;
    for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        (depth_at(mid) < p.depth ? lo : hi) = mid;
    }
    p.alpha = static_cast<float>(0.5 * (lo + hi));
    // The table's interpolation: the depth the profile reaches is the depth at this α.
    p.depth = static_cast<float>(depth_at(p.alpha));
    return p;
}

/// A segment of a curve, in pixel coordinates (x right, y down; pixel centres at integers).
struct Segment {
    Vec2 a{0, 0}, b{0, 0};
    std::uint32_t curve = 0, point = 0; ///< the curve and its first point's index
    double extent = 0;                  ///< m: the farthest the groove (or the curl) reaches
    double reach = 0;                   ///< m: the extent and the fade beyond it
    Vec2 before{0, 0}, after{0, 0};     ///< the curve's points before a and after b (= a, b at an end)
    bool cap_a = false, cap_b = false;  ///< the curve ends at a (b): a round cap of the whole reach
    double scan = 0;                    ///< m: how far from the segment pixels are scanned (its curve's widest reach)
};

/// The nearest few distinct curves of a pixel: each curve's distance (the least over its
/// segments) and where on which segment it is met (the profile is interpolated there when the
/// curves are joined: most offers are overtaken by a nearer one).
struct alignas(64) Nearest {
    static constexpr int SLOTS = 4;
    std::array<float, SLOTS> distance{};
    std::array<std::int32_t, SLOTS> curve{-1, -1, -1, -1};
    std::array<std::uint32_t, SLOTS> segment{};
    std::array<float, SLOTS> t{};

    void offer(float d, std::int32_t c, std::uint32_t k, double at) {
        int slot = -1, farthest = 0;
        for (int i = 0; i < SLOTS; ++i) {
            if (curve[i] == c) slot = i;
            if (curve[i] < 0 || (curve[farthest] >= 0 && distance[i] > distance[farthest])) farthest = i;
        }
        if (slot < 0) {
            if (curve[farthest] >= 0 && distance[farthest] <= d) return;
            slot = farthest;
        } else if (distance[slot] <= d) {
            return;
        }
        curve[slot] = c, distance[slot] = d, segment[slot] = k, t[slot] = static_cast<float>(at);
    }
};

/// The curves' distances joined by a smooth minimum, −r·ln Σ exp(−dᵢ/r) (symmetric in the
/// curves, so the join does not depend on their order, and smooth), and their profiles blended
/// with the weights exp(−dᵢ/r) / Σ: where two cracks meet, the plate's corner is rounded in plan
/// by about r, and the ridge between two grooves has a rounded crest, with no crease along the
/// line of equal distance. A curve nearer than the others by several r keeps its own distance
/// and profile.
template <class ProfileOf, class ExtentOf>
std::pair<double, Profile> join_nearest(const Nearest& n, double r, ProfileOf&& profile_of, ExtentOf&& extent_of) {
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < Nearest::SLOTS; ++k)
        if (n.curve[k] >= 0) least = std::min(least, double(n.distance[k]));
    // Each curve's terms fade out beyond its groove's extent (over FADE of it), so a curve
    // leaves the join smoothly where its scan ends and never bends its own groove. The profiles blend over a longer
    // distance than the distances join (PROFILE_BLEND × r): a later, shallower crack's floor meets the deeper one it
    // ends on by a gentle step.
    std::array<double, Nearest::SLOTS> w{};
    double sum = 0;
    for (int k = 0; k < Nearest::SLOTS; ++k) {
        if (n.curve[k] < 0) continue;
        const double fade = (1.0 - smooth01((n.distance[k] / std::max(extent_of(k), 1e-12) - 1.0) / FADE))
                            * smooth01(profile_of(k).share / SHALLOW);
        sum += fade * std::exp(-(n.distance[k] - least) / r);
        w[k] = fade * std::exp(-(n.distance[k] - least) / (PROFILE_BLEND * r));
    }
    if (sum <= 1e-12) return {std::numeric_limits<double>::infinity(), Profile{}};
    Profile p;
    double seen = 0;
    for (int k = 0; k < Nearest::SLOTS; ++k) {
        if (w[k] <= 0) continue;
        p = seen == 0 ? profile_of(k) : lerp(p, profile_of(k), w[k] / (seen + w[k]));
        seen += w[k];
    }
    return {std::max(least - r * std::log(sum), 0.0), p};
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
    std::vector<std::vector<Profile>> profiles(curves.size());
    std::vector<Segment> segs;
    parallel_rows(static_cast<int>(curves.size()), [&](int curve) {
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
    });
    for (std::size_t c = 0; c < curves.size(); ++c) {
        const CrackCurve& cv = curves[c];
        for (std::size_t i = 0; i + 1 < cv.uv.size(); ++i) {
            Segment s;
            s.a = to_px(cv.uv[i]);
            s.b = to_px(cv.uv[i + 1]);
            s.curve = static_cast<std::uint32_t>(c);
            s.point = static_cast<std::uint32_t>(i);
            const Profile &p = profiles[c][i], &q = profiles[c][i + 1];
            // The groove's extent, and the scan beyond it over which the curve fades out of the join.
            s.extent = std::max(p.floor + std::max(double(p.reach), o.curl > 0 ? o.curl_reach : 0.0),
                                q.floor + std::max(double(q.reach), o.curl > 0 ? o.curl_reach : 0.0));
            s.reach = (1.0 + FADE) * s.extent;
            segs.push_back(s);
        }
    }
    // Past a joint the rectangle reaches only as far as the pixels whose nearest point of the
    // curve is the joint itself (the wedge on the bend's outer side, Mauch 2000): reach · sin θ
    // for a turn θ ≤ 90°, set per row below in that row's metres. At the curve's ends, a round
    // cap of the whole reach.
    for (std::size_t k = 0, first = 0; k < segs.size(); ++k) {
        Segment& s = segs[k];
        const CrackCurve& cv = curves[s.curve];
        const std::size_t n = cv.uv.size(), i = s.point;
        if (i == 0) first = k;
        // A loop may close on its image a period on (round the trunk): its neighbours across
        // the closing point are brought back by that period.
        const Vec2 period = to_px(cv.uv.back()) - to_px(cv.uv.front());
        if (i > 0) {
            s.before = segs[k - 1].a;
        } else if (cv.closed && n > 2) {
            s.before = to_px(cv.uv[n - 2]) - period;
        } else {
            s.before = s.a, s.cap_a = true;
        }
        if (i + 2 < n) {
            s.after = to_px(cv.uv[i + 2]);
        } else if (cv.closed && n > 2) {
            s.after = segs[first].b + period;
        } else {
            s.after = s.b, s.cap_b = true;
        }
    }

    // Every segment of a curve scans as wide as the curve's widest reach: each pixel within it
    // then finds its nearest point of the curve, whose profile alone shapes it (a narrower groove
    // ahead, as at a tapering tip, is not overlapped by the round end of a wider one behind).
    for (std::size_t k0 = 0; k0 < segs.size();) {
        std::size_t k1 = k0;
        double widest = 0;
        for (; k1 < segs.size() && segs[k1].curve == segs[k0].curve; ++k1)
            widest = std::max(widest, segs[k1].reach);
        for (std::size_t k = k0; k < k1; ++k)
            segs[k].scan = widest;
        k0 = k1;
    }

    // === Bin the segments (and their periodic images in v) by blocks of rows.
    const int blocks = (H + BLOCK_ROWS - 1) / BLOCK_ROWS;
    std::vector<std::vector<std::pair<std::uint32_t, double>>> bins(static_cast<std::size_t>(blocks));
    for (std::size_t k = 0; k < segs.size(); ++k) {
        const Segment& s = segs[k];
        // The scanned rectangle reaches at most scan · √2 from the segment in v (its corners).
        const double reach_px = std::sqrt(2.0) * s.scan / g.metres_v + 1 + HALO;
        const double y0 = std::min(s.a.y(), s.b.y()) - reach_px, y1 = std::max(s.a.y(), s.b.y()) + reach_px;
        std::vector<double> shifts{0.0};
        if (g.wrap_v) {
            const double base = -H * std::floor(std::min(s.a.y(), s.b.y()) / H);
            shifts = {base - H, base, base + H};
        }
        for (double shift : shifts) {
            const int b0 = std::max(0, static_cast<int>(std::floor((y0 + shift) / BLOCK_ROWS)));
            const int b1 = std::min(blocks - 1, static_cast<int>(std::floor((y1 + shift) / BLOCK_ROWS)));
            for (int b = b0; b <= b1; ++b)
                bins[static_cast<std::size_t>(b)].emplace_back(static_cast<std::uint32_t>(k), shift);
        }
    }

    parallel_rows(blocks, [&](int block) {
        // The block's rows and a halo of HALO rows each side (wrapped in v, or left empty past
        // the map's edge), for the profiles' smoothing.
        const int r0 = block * BLOCK_ROWS, r1 = std::min(H, r0 + BLOCK_ROWS), h0 = r0 - HALO, rows = r1 - r0 + 2 * HALO;
        auto grid_row = [&](int y) { return g.wrap_v ? ((y % H) + H) % H : (y >= 0 && y < H ? y : -1); };
        std::vector<Nearest> state(static_cast<std::size_t>(rows * W));
        for (const auto& [k, shift] : bins[static_cast<std::size_t>(block)]) {
            const Segment& s = segs[k];
            const auto curve = static_cast<std::int32_t>(s.curve);
            // The segment and its rectangle in a row's metres (recomputed only where the metres
            // per pixel in u change: on the sphere).
            double mu = -1;
            const double mv = g.metres_v;
            Vec2 a(0, 0), ab(0, 0);
            double len = 0;
            const double scan2 = s.scan * s.scan;
            std::array<Vec2, 4> corner{a, a, a, a};
            for (int y = h0; y < h0 + rows; ++y) {
                if (grid_row(y) < 0) continue;
                if (const double row_mu = g.metres_u[static_cast<std::size_t>(grid_row(y))]; row_mu != mu) {
                    mu = row_mu;
                    a = Vec2(s.a.x() * mu, (s.a.y() + shift) * mv);
                    const Vec2 b(s.b.x() * mu, (s.b.y() + shift) * mv);
                    ab = b - a;
                    len = ab.norm();
                    const Vec2 dir = len > 0 ? Vec2(ab / len) : Vec2(1, 0), nrm(-dir.y(), dir.x());
                    // How far past a joint the wedge of pixels nearest to it reaches (plus a
                    // margin), and on which side: the wedge lies on the bend's outer side, away
                    // from the neighbouring point (the inner side is in the slabs of the
                    // segments either side). Each segment's rectangle is extended there only.
                    auto past = [&](const Vec2& from, const Vec2& to, bool cap) {
                        const Vec2 d((to.x() - from.x()) * mu, (to.y() - from.y()) * mv);
                        const double dn = d.norm();
                        if (cap || dn <= 0) return s.scan;
                        const double cos_turn = d.dot(dir) / dn;
                        if (cos_turn <= 0) return s.scan;
                        return std::min(s.scan, s.scan * std::sqrt(std::max(0.0, 1.0 - cos_turn * cos_turn))
                                                    + o.wedge_margin_px * std::max(mu, mv));
                    };
                    // The side (+1: along nrm) where the neighbour beyond an end lies.
                    auto side = [&](const Vec2& neighbour, const Vec2& end) {
                        return Vec2((neighbour.x() - end.x()) * mu, (neighbour.y() - end.y()) * mv).dot(nrm) > 0 ? 1
                                                                                                                 : -1;
                    };
                    const double pa = past(s.before, s.a, s.cap_a), pb = past(s.b, s.after, s.cap_b);
                    const bool round_a = s.cap_a || pa >= s.scan, round_b = s.cap_b || pb >= s.scan;
                    const int sa = side(s.before, s.a), sb = side(s.after, s.b);
                    // A corner on the +nrm side is extended when the neighbour lies on the − side.
                    auto at_a = [&](int sign) {
                        return a - dir * ((round_a || sa != sign) ? pa : 0.0) + sign * nrm * s.scan;
                    };
                    auto at_b = [&](int sign) {
                        return b + dir * ((round_b || sb != sign) ? pb : 0.0) + sign * nrm * s.scan;
                    };
                    corner = {at_a(1), at_b(1), at_b(-1), at_a(-1)};
                }
                const double ym = y * mv;
                double xlo = 1e300, xhi = -1e300;
                for (int e = 0; e < 4; ++e) {
                    const Vec2 &p = corner[static_cast<std::size_t>(e)],
                               &q = corner[static_cast<std::size_t>((e + 1) % 4)];
                    if ((p.y() - ym) * (q.y() - ym) > 0 || p.y() == q.y()) continue;
                    const double x = p.x() + (ym - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
                    xlo = std::min(xlo, x);
                    xhi = std::max(xhi, x);
                }
                if (xlo > xhi) continue;
                int x0 = static_cast<int>(std::ceil(xlo / mu)), x1 = static_cast<int>(std::floor(xhi / mu));
                if (x1 - x0 >= W) {
                    // Near the sphere's poles a row's rectangle can be wider than the period: each
                    // column then has several images in it, and its distance, convex along the
                    // row, is least at one of the two images either side of the row's closest
                    // point to the segment. Scan those.
                    const double ty = ab.y() != 0 ? std::clamp((ym - a.y()) / ab.y(), 0.0, 1.0) : 0.0;
                    const int closest = static_cast<int>(std::floor((a.x() + ty * ab.x()) / mu));
                    x0 = std::max(x0, closest - W + 1);
                    x1 = std::min(x1, closest + W);
                }
                Nearest* row = &state[static_cast<std::size_t>((y - h0) * W)];
                for (int x = x0, wrapped = ((x0 % W) + W) % W; x <= x1;
                     ++x, wrapped = wrapped + 1 < W ? wrapped + 1 : 0) {
                    const Vec2 q(x * mu, ym);
                    const double t = len > 0 ? std::clamp((q - a).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
                    const double d2 = (q - a - t * ab).squaredNorm();
                    if (d2 > scan2) continue;
                    const double d = std::sqrt(d2);
                    row[wrapped].offer(static_cast<float>(d), curve, k, t);
                }
            }
        }
        // === Where grooves meet, their distances join smoothly (join_nearest); the profiles are
        // smoothed over the block and its halo.
        ProfileWindow window(W, rows);
        std::vector<float> distance(static_cast<std::size_t>(rows * W), std::numeric_limits<float>::infinity());
        for (int row = 0; row < rows; ++row)
            for (int x = 0; x < W; ++x) {
                const std::size_t j = static_cast<std::size_t>(row * W + x);
                const Nearest& n = state[j];
                if (std::all_of(n.curve.begin(), n.curve.end(), [](std::int32_t c) { return c < 0; })) continue;
                const auto [d, p] = join_nearest(
                    n, o.join_radius,
                    [&](int slot) {
                        const Segment& s = segs[n.segment[static_cast<std::size_t>(slot)]];
                        return lerp(profiles[s.curve][s.point], profiles[s.curve][s.point + 1],
                                    n.t[static_cast<std::size_t>(slot)]);
                    },
                    [&](int slot) {
                        return double(static_cast<float>(segs[n.segment[static_cast<std::size_t>(slot)]].extent));
                    });
                if (!std::isfinite(d)) continue;
                distance[j] = static_cast<float>(d);
                window.put(x, row, p);
            }
        window.smooth(PROFILE_SMOOTH_PX);
        // === The groove's drop, the curl's lift and the floor's coverage from the joined distance.
        for (int y = r0; y < r1; ++y) {
            const double pixel = std::min(g.metres_u[static_cast<std::size_t>(y)], g.metres_v);
            for (int x = 0; x < W; ++x) {
                const double d = distance[static_cast<std::size_t>((y - h0) * W + x)];
                const std::optional<Profile> found = window.profile(x, y - h0);
                if (!std::isfinite(d) || !found) continue;
                const Profile& p = *found;
                const std::size_t i = g.index(x, y);
                const double share = p.depth > 0 ? p.share * p.drop(d, fillets) / p.depth : 0.0;
                // Curl lifts the rim as the post stage does (Fig. 4.11): by curl · (1 − d/reach)²
                // from the plate's edge (the floor's), concave, highest at the lip; the distance from the
                // floor's edge is eased over the floor fillet, so the lift meets the floor without a crease.
                const double fb = std::max(double(p.fillet_bottom), 1e-12);
                double from_lip = std::max(0.0, d - p.floor);
                from_lip = from_lip < fb ? from_lip * from_lip / (2 * fb) : from_lip - 0.5 * fb;
                const double lift =
                    o.curl > 0 && o.curl_reach > 0 ? o.curl * sqr(std::max(0.0, 1.0 - from_lip / o.curl_reach)) : 0.0;
                const double half = std::max(double(p.gap), 0.5 * pixel);
                out.drop[i] = static_cast<float>(top[i] * std::clamp(share, 0.0, 1.0));
                out.lift[i] = static_cast<float>(top[i] * lift);
                out.coverage[i] = static_cast<float>(std::clamp((half - d) / pixel + 0.5, 0.0, 1.0));
                out.age[i] = p.age;
                out.distance[i] = static_cast<float>(d);
            }
        }
    });
    return out;
}

} // namespace crackle::render
