#include "render/groove.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "render/fillet.hpp"
#include "render/groove_profile.hpp"
#include "render/groove_scan.hpp"
#include "render/relief.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace crackle::render {

namespace {

using groove::curl_lift;
using groove::kept_points;
using groove::Profile;
using groove::ProfileWindow;
using groove::SHALLOW;
using groove::smooth01;
using groove::smooth_along;
using groove::solve;

/// Rows scanned and joined together: the halo's rows (HALO each side) are scanned twice, 9 % more
/// work at 64 rows, 5 % at 128.
constexpr int BLOCK_ROWS = 128;
constexpr double PROFILE_BLEND = 4.0;
/// Beyond its groove's extent a curve fades out of the join over this share of the extent.
constexpr double FADE = 0.4;
/// The curves are scanned in parts about this many times their scan width long: a pixel keeps
/// each part's nearest point, so a curve that comes back beside itself keeps both stretches
/// unless both lie in one part (a bend tighter than the part, where the two stretches are near
/// along the curve too). Shorter parts would keep more apart, at more slots a pixel.
constexpr double PART = 2.0;
/// The steepest turn of a groove's slope between neighbouring pixels anywhere on a fillet:
/// narrower features would show as creases (the bound is 10° between neighbours).
constexpr double TURN_PER_PIXEL = 9.0 * PI / 180.0;
/// The profiles' parameters are smoothed over about this many pixels: a pixel's nearest point of a
/// curve jumps across the inner side of a bend (and its nearest curves change where they meet),
/// and the profile with it.
constexpr int PROFILE_SMOOTH_PX = 1;
/// Rows of a block's halo: the reach of the profiles' smoothing.
constexpr int HALO = 3 * PROFILE_SMOOTH_PX;

/// How distinct two nearest points of one curve are, from how far apart they lie along it (Δs)
/// against their distances from the pixel (d₁ + d₂): 0 up to Δs = DISTINCT_FROM · (d₁ + d₂) (the
/// points of a half circle round the pixel are one neighbourhood: the inner side of a bend), 1
/// from DISTINCT_FROM + DISTINCT_OVER on (the arms of a hairpin, a chain's end beside its middle).
constexpr double DISTINCT_FROM = 1.6, DISTINCT_OVER = 2.0;

/// Where a slot's curve is met: how far along it (m), and the length of the loop it closes (0: not
/// a loop).
struct Along {
    double arc = 0, loop = 0;
};

/// The curves' distances joined by a smooth minimum, −r·ln Σ exp(−dᵢ/r) (symmetric in the
/// curves, so the join does not depend on their order, and smooth), and their profiles blended
/// with the weights exp(−dᵢ/r) / Σ: where two cracks meet, the plate's corner is rounded in plan
/// by about r, and the ridge between two grooves has a rounded crest, with no crease along the
/// line of equal distance. A curve nearer than the others by several r keeps its own distance
/// and profile.
/// The slots are curve parts (render/groove_scan.hpp): two of one curve count as two curves as
/// far as their points are distinct along it (`DISTINCT_FROM`), and as one (the nearer) where
/// they are neighbours, so a curve that comes back beside itself joins its two stretches as two
/// curves would, and its nearest point never jumps between them with their profiles.
template <class ShareOf, class ProfileOf, class ExtentOf, class ChainOf, class AlongOf>
std::pair<double, Profile> join_nearest(const scan::Nearest& n, double r, ShareOf&& share_of, ProfileOf&& profile_of,
                                        ExtentOf&& extent_of, ChainOf&& chain_of, AlongOf&& along_of) {
    constexpr int SLOTS = scan::Nearest::SLOTS;
    // Each curve's terms fade out beyond its groove's extent (over FADE of it), so a curve
    // leaves the join smoothly where its scan ends and never bends its own groove. The profiles blend over a longer
    // distance than the distances join (PROFILE_BLEND × r): a later, shallower crack's floor meets the deeper one it
    // ends on by a gentle step. (A curve's whole profile is interpolated only where it is blended:
    // the fade needs its share alone.)
    std::array<double, SLOTS> fade{}, w{};
    // The nearest of the curves that take part: a faded-out curve nearer than them must not be
    // the reference of the exponentials (their terms would underflow beyond ~28 r, and the
    // grooves vanish along the edge of its scan).
    double least = std::numeric_limits<double>::infinity();
    std::array<std::uint32_t, SLOTS> chain{};
    bool twice = false; // a curve in two slots
    for (int k = 0; k < SLOTS; ++k) {
        const auto K = static_cast<std::size_t>(k);
        if (n.curve[K] < 0) continue;
        chain[K] = chain_of(k);
        for (int j = 0; j < k; ++j)
            twice |= n.curve[static_cast<std::size_t>(j)] >= 0 && chain[static_cast<std::size_t>(j)] == chain[K];
        const double beyond_extent = smooth01((n.distance[K] / std::max(extent_of(k), 1e-12) - 1.0) / FADE);
        if (beyond_extent >= 1.0) continue; // faded out
        fade[K] = (1.0 - beyond_extent) * smooth01(share_of(k) / SHALLOW);
        if (fade[K] > 0) least = std::min(least, double(n.distance[K]));
    }
    if (!std::isfinite(least)) return {std::numeric_limits<double>::infinity(), Profile{}};
    // Two parts of one curve: the farther counts as far as it is distinct from each nearer one
    // (faded or not: where the two are one neighbourhood of the curve, the nearest point alone
    // shapes the groove, as it did with one entry per curve). Where two neighbours swap, their
    // fades are alike (the share and the extent vary smoothly along a curve).
    std::array<double, SLOTS> counts;
    counts.fill(1.0);
    if (twice) {
        for (int k = 0; k < SLOTS; ++k)
            for (int j = 0; j < SLOTS; ++j) {
                const auto K = static_cast<std::size_t>(k), J = static_cast<std::size_t>(j);
                if (j == k || fade[K] <= 0 || n.curve[J] < 0 || chain[K] != chain[J]) continue;
                if (n.distance[J] > n.distance[K] || (n.distance[J] == n.distance[K] && j > k)) continue;
                const Along at_k = along_of(k), at_j = along_of(j);
                double apart = std::abs(at_k.arc - at_j.arc);
                if (at_k.loop > 0) apart = std::min(apart, at_k.loop - apart);
                counts[K] *= smooth01((apart / std::max(double(n.distance[K]) + n.distance[J], 1e-12) - DISTINCT_FROM)
                                      / DISTINCT_OVER);
            }
    }
    double sum = 0;
    for (int k = 0; k < SLOTS; ++k) {
        const auto K = static_cast<std::size_t>(k);
        if (fade[K] <= 0) continue;
        const double beyond = n.distance[K] - least; // exp(−0) = 1 exactly: the nearest curve's terms
        sum += counts[K] * fade[K] * (beyond > 0 ? std::exp(-beyond / r) : 1.0);
        w[K] = counts[K] * fade[K] * (beyond > 0 ? std::exp(-beyond / (PROFILE_BLEND * r)) : 1.0);
    }
    Profile p;
    double seen = 0;
    for (int k = 0; k < SLOTS; ++k) {
        if (w[k] <= 0) continue;
        p = seen == 0 ? profile_of(k) : lerp(p, profile_of(k), w[k] / (seen + w[k]));
        seen += w[k];
    }
    if (seen <= 0) return {std::numeric_limits<double>::infinity(), Profile{}};
    return {std::max(least - r * (sum == 1.0 ? 0.0 : std::log(sum)), 0.0), p}; // ln 1 = 0 exactly: one curve
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
    std::uint32_t curve = 0;
    float arc = 0, length = 0, loop = 0; ///< m: along the curve to a; the segment's; a loop's whole (0: open)
};

std::vector<SegmentEnds> segment_ends(const std::vector<scan::Segment>& segs,
                                      const std::vector<std::vector<Profile>>& profiles,
                                      const std::vector<bool>& loop) {
    std::vector<SegmentEnds> ends(segs.size());
    for (std::size_t k = 0; k < segs.size(); ++k)
        ends[k] = {profiles[segs[k].curve][segs[k].point],
                   profiles[segs[k].curve][segs[k].point + 1],
                   static_cast<float>(segs[k].extent),
                   segs[k].curve,
                   static_cast<float>(segs[k].arc),
                   static_cast<float>(segs[k].length),
                   static_cast<float>(loop[segs[k].curve] ? segs[k].curve_length : 0.0)};
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
                [&](int slot) { // as lerp() interpolates the share
                    const SegmentEnds& e = ends[n.segment[static_cast<std::size_t>(slot)]];
                    const double t = n.t[static_cast<std::size_t>(slot)];
                    return static_cast<float>((1 - t) * e.a.share + t * e.b.share);
                },
                [&](int slot) {
                    const SegmentEnds& e = ends[n.segment[static_cast<std::size_t>(slot)]];
                    return lerp(e.a, e.b, n.t[static_cast<std::size_t>(slot)]);
                },
                [&](int slot) { return double(ends[n.segment[static_cast<std::size_t>(slot)]].extent); },
                [&](int slot) { return ends[n.segment[static_cast<std::size_t>(slot)]].curve; },
                [&](int slot) {
                    const SegmentEnds& e = ends[n.segment[static_cast<std::size_t>(slot)]];
                    return Along{e.arc + double(n.t[static_cast<std::size_t>(slot)]) * e.length, e.loop};
                });
            if (!std::isfinite(d)) continue;
            j.distance[i] = static_cast<float>(d);
            j.window.put(x, row, p);
        }
    j.window.smooth(PROFILE_SMOOTH_PX);
    return j;
}

/// The smoothed plate height, opening and crack weight at each point of a curve, and its arc
/// length in pixels.
struct AlongCurve {
    std::vector<double> top, opening, weight, arc;
};

/// The fillets' fastest turns (α per fillet length) and the pixel the shapes are sized for.
struct ProfileRates {
    double top, bottom, shape_pixel;
};

/// The groove's profile at point i of a curve: depth, floor, reach and fillets from the plates'
/// height, the opening and the crack weight there, solved for its wall (groove_profile.hpp).
Profile point_profile(const CrackCurve& cv, const AlongCurve& along, std::size_t i, const GrooveOptions& o,
                      const Fillets& fillets, const ProfileRates& rates) {
    const double taper = cv.taper[i], w = along.weight[i];
    Profile p;
    double share = std::min(1.0, o.crack_depth * std::sqrt(w));
    if (o.crack_depth <= 0) {
        // bake.crack_depth = 0 leaves the depth to the simulation: a closed crack is cut
        // by the bevel only, one that post.shrinkage opened goes through the layer to the
        // ground, as the raster bake's gaps do (table-5-2-*).
        const double bevel = along.top[i] > 0 ? std::min(1.0, o.bevel / along.top[i]) : 0.0;
        share = bevel + (1.0 - bevel) * smooth01(along.opening[i] / o.pixel);
    }
    p.share = static_cast<float>(share * taper);
    p.floor = static_cast<float>(0.5 * along.opening[i] * taper);
    // A crack closes at its tip: the floor narrows over its groove's own width (its
    // extent), so the walls meet at the tip in a rounded point, not a crease.
    const double from_tip =
        std::min(cv.tip_front ? along.arc[i] : 1e300, cv.tip_back ? along.arc.back() - along.arc[i] : 1e300);
    if (from_tip < 1e300) {
        const double extent_px = (p.floor + std::max(o.rounding, o.crack_width * w)) / o.pixel;
        p.floor = static_cast<float>(p.floor * smooth01(from_tip / std::max(extent_px, 1.0)));
    }
    p.depth = static_cast<float>(along.top[i] * p.share);
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
        least = std::max(least, wall / TURN_PER_PIXEL * rates.shape_pixel);
        least_floor = std::max(least_floor, fillets.shown(wall) / TURN_PER_PIXEL * rates.shape_pixel);
        p.fillet_bottom = static_cast<float>(std::max(o.rounding, least_floor * rates.bottom));
        p.fillet_top = static_cast<float>(std::max({o.rounding, least * rates.top, double(p.reach - p.fillet_bottom)}));
        solved = solve(p, fillets);
    }
    // The simulated opening is the gap between the plates' lips: the floor fillets (the
    // walls' feet) stand inside it, so the trough is the opening plus the walls and lip
    // fillets (with a floor as wide as the opening and the floor fillets beside it, mud's
    // plates read as pebbles on a bed of dirt). The Mask's core stays the whole gap.
    solved.gap = solved.floor;
    solved.floor = std::max(0.0f, solved.floor - solved.fillet_bottom);
    return solved;
}

/// The step (pixels) of the grid the curl's lift is measured on: the coarsest power of two that
/// divides the map with a step at most a third of the join radius (1 on the sphere's map).
int lift_step(const PixelGrid& g, const GrooveOptions& o) {
    int k = o.lift_step_px;
    if (k <= 0)
        for (k = 1; g.wrap_v && 2 * k * o.pixel <= o.join_radius / 3.0 * (1 + 1e-9) && g.width % (2 * k) == 0
                    && g.height % (2 * k) == 0;)
            k *= 2;
    return k;
}

/// The grid k times coarser than g; each row's metres those at the coarse row's middle.
PixelGrid coarser_grid(const PixelGrid& g, int k) {
    PixelGrid coarse;
    coarse.width = g.width / k;
    coarse.height = g.height / k;
    coarse.wrap_v = g.wrap_v;
    coarse.metres_v = g.metres_v * k;
    for (int y = 0; y < coarse.height; ++y) // the rows' metres at the coarse row's middle
        coarse.metres_u.push_back(k * 0.5
                                  * (g.metres_u[static_cast<std::size_t>(k * y + (k - 1) / 2)]
                                     + g.metres_u[static_cast<std::size_t>(k * y + k / 2)]));
    return coarse;
}

/// How far from each curve point its groove reaches (floor and reach, at least `beyond`).
std::vector<std::vector<double>> groove_extents(const std::vector<std::vector<Profile>>& of, double beyond) {
    std::vector<std::vector<double>> e(of.size());
    for (std::size_t c = 0; c < of.size(); ++c)
        for (const Profile& p : of[c])
            e[c].push_back(p.floor + std::max(double(p.reach), beyond));
    return e;
}

/// The curl's lift on the coarse grid: each coarse pixel's joined distance to the curves, within
/// the lift's reach, and the lift there (interpolated onto the map afterwards).
std::vector<float> coarse_lift(const PixelGrid& coarse, const std::vector<CrackCurve>& coarse_reduced,
                               const std::vector<std::vector<Profile>>& coarse_profiles, const std::vector<bool>& loops,
                               const GrooveOptions& o) {
    std::vector<float> lift(coarse.pixels(), 0.0f);
    {
        const std::vector<scan::Segment> segs =
            scan::segments(coarse, coarse_reduced, groove_extents(coarse_profiles, o.curl_reach), FADE, PART);
        const std::vector<scan::Bin> bins = scan::bins(coarse, segs, BLOCK_ROWS, HALO);
        const std::vector<SegmentEnds> ends = segment_ends(segs, coarse_profiles, loops);
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
    return lift;
}

/// The grooves: each pixel's distance to the curves within their grooves' extent, joined where
/// grooves meet, and the profile there: the drop, the Mask's coverage, the age, the distance and,
/// with curl, the lift near the lips (`own_lift`: how much of it is the groove's own).
void scan_grooves(const PixelGrid& g, const std::vector<CrackCurve>& reduced,
                  const std::vector<std::vector<Profile>>& profiles, const std::vector<bool>& loops,
                  const GrooveOptions& o, const Fillets& fillets, const std::vector<float>& top, GrooveField& out,
                  std::vector<float>& own_lift) {
    const int W = g.width;
    const bool curl = o.curl > 0 && o.curl_reach > 0;
    {
        const std::vector<scan::Segment> segs = scan::segments(g, reduced, groove_extents(profiles, 0.0), FADE, PART);
        const std::vector<scan::Bin> bins = scan::bins(g, segs, BLOCK_ROWS, HALO);
        const std::vector<SegmentEnds> ends = segment_ends(segs, profiles, loops);
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
    const ProfileRates rates{fillets.top.steepest_turn(), fillets.bottom.steepest_turn(),
                             o.shape_pixel > 0 ? o.shape_pixel : o.pixel};
    // === The curl's lift reaches a few layer heights from the lip, far beyond most grooves, and
    // varies there on the scale of the reach and of the join's rounding: it is measured on a grid
    // coarser by k (its step at most a third of the join radius) and interpolated bicubically.
    const bool curl = o.curl > 0 && o.curl_reach > 0;
    // On the sphere's map (rows of shrinking width) the coarser grid was 2.9 % of the lift and 4°
    // (99th percentile of the normals) off in the tests: there the lift is measured at every pixel.
    const int k = lift_step(g, o);
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
        AlongCurve along{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
                         std::vector<double>(n, 0.0)};
        for (std::size_t i = 0; i < n; ++i) {
            along.top[i] = top_at(to_px(cv.uv[i]));
            along.opening[i] = cv.opening[i];
            along.weight[i] = cv.weight[i];
            if (i > 0) along.arc[i] = along.arc[i - 1] + (to_px(cv.uv[i]) - to_px(cv.uv[i - 1])).norm();
        }
        for (std::vector<double>* values : {&along.top, &along.opening, &along.weight})
            *values = smooth_along(along.arc, *values, o.smoothing_px, cv.closed);
        std::vector<Vec2> at(n);
        for (std::size_t i = 0; i < n; ++i)
            at[i] = to_px(cv.uv[i]);
        const double max_top = n > 0 ? *std::max_element(along.top.begin(), along.top.end()) : 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            profiles[c][i] = point_profile(cv, along, i, o, fillets, rates);
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
    // Within the groove, the lift is shaped by the groove's own distance; from half its extent
    // outwards it blends into the lift field (below), which reaches farther at a coarser step.
    std::vector<float> own_lift(curl ? px : 0, 0.0f);
    std::vector<bool> loops(curves.size());
    for (std::size_t c = 0; c < curves.size(); ++c)
        loops[c] = curves[c].closed;
    Timer timer;
    scan_grooves(g, reduced, profiles, loops, o, fillets, top, out, own_lift);
    const double t_grooves = timer.seconds();
    if (!curl) return out;

    const PixelGrid coarse = coarser_grid(g, k);
    const std::vector<float> lift = coarse_lift(coarse, coarse_reduced, coarse_profiles, loops, o);
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
