// Grooves from crack curves in the presets' bakes (render/crack_curves, render/groove, issue 35):
// the curves keep the simulated chains' ends and stay within a quarter element (plus the wander)
// of them, with no kinks at the element-length vertices; baked mud, bark and fruit at 2048² show
// no faceted walls or steps next to the cracks; the grooves keep their shape in metres at every
// map size; the Mask keeps the pieces and the junctions where they meet.
#include "app/run/options.hpp"
#include "app/run/pipeline.hpp"
#include "fracture/statistics.hpp"
#include "io/preset.hpp"
#include "render/bake.hpp"
#include "render/crack_curves.hpp"
#include "render/groove.hpp"
#include "render/shading.hpp"
#include "support/gl_support.hpp"
#include "support/presets.hpp"
#include "support/regions.hpp"
#include "support/simulated.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>

using namespace crackle;
using render::PixelGrid;
using test::simulate;
using test::Simulated;

namespace {

/// Pixels where the height jumps: a neighbour more than 0.15 mm away and more than 3× the
/// differences on either side (a step in a surface, not a steep wall).
int steps(const render::TextureSet& set) {
    const int w = set.width, h = set.height_px;
    auto at = [&](int x, int y) {
        return double(set.height[std::size_t(((y % h) + h) % h) * std::size_t(w) + std::size_t(((x % w) + w) % w)]);
    };
    int count = 0;
    for (int y = 1; y + 2 < h; ++y) // (v is not followed round: the sphere's map ends at the poles)
        for (int x = 0; x < w; ++x)
            for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
                const double jump = std::abs(at(x + dx, y + dy) - at(x, y));
                const double before = std::abs(at(x, y) - at(x - dx, y - dy)),
                             after = std::abs(at(x + 2 * dx, y + 2 * dy) - at(x + dx, y + dy));
                count += jump > 1.5e-4 && jump > 3 * std::max(before, after);
            }
    return count;
}

/// Share of the paths' total turning (|angle| between successive directions, each path
/// resampled every `step` metres) that happens within `window` metres of the vertices of the
/// simulated chains (`vertices[i]` for `paths[i]`, texture coordinates): 1 when the paths turn only
/// at the element-length vertices (kinks), about 2·window / (vertex spacing) when the turning
/// is spread along them.
double vertex_turning_share(const post::PieceMesh& p, const std::vector<std::vector<Vec2>>& paths,
                            const std::vector<std::vector<Vec2>>& vertices, double step, double window) {
    auto metres = [&](const Vec2& q) { return Vec2(q.x() * render::metres_per_u(p, q.y()), q.y() * p.tile_size.y()); };
    double all = 0, near = 0;
    for (std::size_t c = 0; c < paths.size(); ++c) {
        std::vector<Vec2> pts, corners;
        for (const Vec2& q : paths[c])
            pts.push_back(metres(q));
        for (const Vec2& q : vertices[c])
            corners.push_back(metres(q));
        std::vector<Vec2> samples{pts.front()};
        double carried = 0;
        for (std::size_t i = 1; i < pts.size(); ++i) {
            const Vec2 d = pts[i] - pts[i - 1];
            const double len = d.norm();
            double at = step - carried;
            for (; at <= len; at += step)
                samples.push_back(pts[i - 1] + d * (at / len));
            carried = len - (at - step);
        }
        for (std::size_t i = 2; i < samples.size(); ++i) {
            const Vec2 a = samples[i - 1] - samples[i - 2], b = samples[i] - samples[i - 1];
            const double turn = std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)));
            double closest = 1e300;
            for (std::size_t k = 1; k + 1 < corners.size(); ++k) // inner vertices: where a polyline kinks
                closest = std::min(closest, (corners[k] - samples[i - 1]).norm());
            all += turn;
            if (closest <= window) near += turn;
        }
    }
    return all > 0 ? near / all : 0.0;
}

/// Connected regions (4-neighbours, periodic in u and v: plane and cylinder tiles) of the pixels
/// whose Mask is below `core`: the plates the baked crack cores separate.
int mask_regions(const render::TextureSet& set, float core) {
    std::vector<int> label;
    return test::label_regions(
        set.width, set.height_px, [&](std::size_t i) { return set.mask[i] < core; },
        [](std::size_t, std::size_t) { return true; }, label);
}

/// Junctions where three or more regions meet, and the three-region ones classified T or Y.
struct Junctions {
    int count = 0;      ///< Σ (k − 2) over the junctions where k regions meet
    int t = 0, y = 0;   ///< three-region junctions classified as the simulation does (statistics.hpp)
    int classified = 0; ///< three-region junctions whose three branches were all found
    std::vector<std::array<double, 3>> at; ///< classified junctions: centre x, y (px) and the largest angle (°)
    double t_share() const { return t + y > 0 ? double(t) / double(t + y) : 0.0; }
};

/// Junctions where three or more regions (labels ≥ 0; −1 between them) meet, on a periodic grid:
/// every pixel between regions takes its nearest region's label (exact distance transform), a 2 × 2
/// block of pixels with three or more labels lies on a junction, blocks touching (8-neighbours)
/// form one junction, and a junction around which k regions meet counts k − 2 (a point where four
/// pieces meet is two junctions a pixel apart, as a map of pieces shows it). Where three regions
/// meet, each branch (the boundary between two of them) is followed out to `reach` pixels: its
/// direction is the principal axis of its boundary pixels between reach / 3 and reach from the
/// junction, and the three angles between the branches classify the junction (T or Y).
Junctions region_junctions(int w, int h, const std::vector<int>& label, int reach = 20) {
    PixelGrid g;
    g.width = w;
    g.height = h;
    g.metres_v = 1;
    g.wrap_v = true;
    g.metres_u.assign(std::size_t(h), 1.0);
    std::vector<std::uint8_t> source(label.size());
    for (std::size_t i = 0; i < label.size(); ++i)
        source[i] = label[i] >= 0;
    const render::DistanceField d = render::distance_transform(g, source, true);
    std::vector<int> near(label.size());
    for (std::size_t i = 0; i < label.size(); ++i)
        near[i] = label[d.nearest[i]];
    auto at = [&](int x, int y) {
        return std::size_t(((y % h) + h) % h) * std::size_t(w) + std::size_t(((x % w) + w) % w);
    };
    auto labels_of = [&](int x, int y, std::vector<int>& into) {
        for (const std::size_t j : {at(x, y), at(x + 1, y), at(x, y + 1), at(x + 1, y + 1)})
            if (std::find(into.begin(), into.end(), near[j]) == into.end()) into.push_back(near[j]);
    };
    std::vector<std::uint8_t> on(label.size(), 0);
    std::vector<int> seen;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            seen.clear();
            labels_of(x, y, seen);
            on[at(x, y)] = seen.size() >= 3;
        }
    Junctions out;
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < on.size(); ++start) {
        if (on[start] != 1) continue;
        on[start] = 2;
        stack.push_back(start);
        seen.clear();
        // The cluster's centre, its pixels unwrapped next to the first one.
        const int x0 = int(start % std::size_t(w)), y0 = int(start / std::size_t(w));
        double sx = 0, sy = 0;
        int n = 0;
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            labels_of(x, y, seen);
            int ux = x - x0, uy = y - y0;
            ux -= w * int(std::lround(double(ux) / w));
            uy -= h * int(std::lround(double(uy) / h));
            sx += ux + 0.5, sy += uy + 0.5, ++n;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx)
                    if (const std::size_t j = at(x + dx, y + dy); on[j] == 1) {
                        on[j] = 2;
                        stack.push_back(j);
                    }
        }
        out.count += static_cast<int>(seen.size()) - 2;
        if (seen.size() != 3) continue;
        const double cx = x0 + sx / n, cy = y0 + sy / n;
        // Each branch: the boundary pixels between two of the three regions in the annulus.
        std::array<double, 3> angle{};
        bool found = true;
        for (int b = 0; b < 3 && found; ++b) {
            const int la = seen[std::size_t(b)], lb = seen[std::size_t((b + 1) % 3)];
            // The branch's line through its boundary pixels (principal axis), pointing away from the
            // junction: its direction does not depend on where in a rounded corner the centre lies.
            double n_px = 0, mx = 0, my = 0, sxx = 0, sxy = 0, syy = 0;
            for (int y = int(cy) - reach - 1; y <= int(cy) + reach + 1; ++y)
                for (int x = int(cx) - reach - 1; x <= int(cx) + reach + 1; ++x) {
                    const double rx = x - cx, ry = y - cy, r = std::hypot(rx, ry);
                    if (r < reach / 3.0 || r > reach || near[at(x, y)] != la) continue;
                    if (near[at(x + 1, y)] == lb || near[at(x - 1, y)] == lb || near[at(x, y + 1)] == lb
                        || near[at(x, y - 1)] == lb)
                        n_px += 1, mx += rx, my += ry, sxx += rx * rx, sxy += rx * ry, syy += ry * ry;
                }
            found = n_px >= 3;
            if (!found) break;
            mx /= n_px, my /= n_px;
            const double cxx = sxx / n_px - mx * mx, cxy = sxy / n_px - mx * my, cyy = syy / n_px - my * my;
            const double axis = 0.5 * std::atan2(2 * cxy, cxx - cyy);
            double ex = std::cos(axis), ey = std::sin(axis);
            if (ex * mx + ey * my < 0) ex = -ex, ey = -ey;
            angle[std::size_t(b)] = std::atan2(ey, ex);
        }
        if (!found) continue;
        ++out.classified;
        std::sort(angle.begin(), angle.end());
        const double deg = 180.0 / PI;
        out.at.push_back({cx, cy,
                          std::max({(angle[1] - angle[0]) * deg, (angle[2] - angle[1]) * deg,
                                    360.0 - (angle[2] - angle[0]) * deg})});
        const fracture::JunctionKind kind = fracture::classify_junction(
            (angle[1] - angle[0]) * deg, (angle[2] - angle[1]) * deg, 360.0 - (angle[2] - angle[0]) * deg);
        out.t += kind == fracture::JunctionKind::T;
        out.y += kind == fracture::JunctionKind::Y;
    }
    return out;
}
/// How the largest angle at each classified junction of `a` changes in `b` (the nearest junction
/// of `b` within 4 px; periodic), in degrees.
struct AngleChange {
    double median = 0, p90 = 0; ///< of |Δ|
    double mean = 0;            ///< of Δ: below 0 where b closes up T's towards Y's
};
AngleChange largest_angle_change(const Junctions& a, const Junctions& b, int w, int h) {
    std::vector<double> diff;
    double sum = 0;
    for (const auto& p : a.at) {
        double best = 1e300, angle = 0;
        for (const auto& q : b.at) {
            double dx = std::abs(q[0] - p[0]), dy = std::abs(q[1] - p[1]);
            dx = std::min(dx, w - dx), dy = std::min(dy, h - dy);
            if (std::hypot(dx, dy) < best) best = std::hypot(dx, dy), angle = q[2];
        }
        if (best <= 4) diff.push_back(std::abs(angle - p[2])), sum += angle - p[2];
    }
    REQUIRE(diff.size() * 10 >= a.at.size() * 9); // nearly every junction found again
    std::sort(diff.begin(), diff.end());
    return {diff[diff.size() / 2], diff[diff.size() * 9 / 10], sum / double(diff.size())};
}
/// The 99th percentile of the angle (degrees) between neighbouring pixels' normals within 6 px
/// of a crack (the Mask > 0.5, its own pixels counted), as the issue measures it on the lit
/// normal map.
double near_crack_p99(const render::TextureSet& set) {
    PixelGrid g;
    g.width = set.width;
    g.height = set.height_px;
    g.metres_v = 1;
    g.metres_u.assign(static_cast<std::size_t>(g.height), 1.0);
    std::vector<std::uint8_t> crack(set.pixels());
    for (std::size_t i = 0; i < crack.size(); ++i)
        crack[i] = set.mask[i] > 0.5f;
    const render::DistanceField d = render::distance_transform(g, crack, false);
    std::vector<double> angles;
    for (int y = 0; y + 1 < g.height; ++y)
        for (int x = 0; x + 1 < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (!(d.distance[i] <= 6.0)) continue;
            const Vec3 a(set.normal[3 * i], set.normal[3 * i + 1], set.normal[3 * i + 2]);
            double worst = 0;
            for (const std::size_t j : {g.index(x + 1, y), g.index(x, y + 1)}) {
                const Vec3 b(set.normal[3 * j], set.normal[3 * j + 1], set.normal[3 * j + 2]);
                worst = std::max(worst, std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * RAD_TO_DEG);
            }
            angles.push_back(worst);
        }
    REQUIRE(angles.size() > 10000);
    const auto k = angles.size() * 99 / 100;
    std::nth_element(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(k), angles.end());
    return angles[k];
}
} // namespace

TEST_SUITE("render") {
    TEST_CASE("crack curves: smoothing keeps every chain's ends and moves no point more than a quarter element, the "
              "wander stays within its amplitude and follows the seed") {
        const Simulated s = simulate("mud", {"simulation.elements=1500"});
        render::CurveOptions o;
        o.metres_per_px = s.pieces.tile_size.y() / 2048;
        const auto smooth = render::crack_curves(s.pieces, o);
        REQUIRE(smooth.size() == s.pieces.chains.size());
        for (std::size_t i = 0; i < smooth.size(); ++i) {
            const post::CrackChain& c = s.pieces.chains[i];
            if (c.closed) continue;
            CHECK((smooth[i].uv.front() - c.uv.front()).norm() < 1e-12);
            CHECK((smooth[i].uv.back() - c.uv.back()).norm() < 1e-12);
            CHECK(smooth[i].uv.size() >= c.uv.size());
        }
        const double moved = render::largest_displacement(s.pieces, smooth);
        CAPTURE(moved);
        CHECK(moved > 0.0);
        CHECK(moved <= 0.25 * 2.0 * s.pieces.element_size); // a quarter of the longest edges (about 2 × the mean)

        o.wander = 0.0005;
        o.wander_wavelength = 0.01;
        const auto wandering = render::crack_curves(s.pieces, o);
        const double wandered = render::largest_displacement(s.pieces, wandering);
        // The wander moves the smoothed points along their normals by up to its amplitude (two
        // octaves: at most 1.4 ×), so the curves stay within that of the smoothed ones.
        double shifted = 0;
        for (std::size_t i = 0; i < smooth.size(); ++i) {
            REQUIRE(wandering[i].uv.size() == smooth[i].uv.size());
            for (std::size_t j = 0; j < smooth[i].uv.size(); ++j) {
                const Vec2 d = wandering[i].uv[j] - smooth[i].uv[j];
                const double mu = render::metres_per_u(s.pieces, smooth[i].uv[j].y());
                shifted = std::max(shifted, Vec2(d.x() * mu, d.y() * s.pieces.tile_size.y()).norm());
            }
        }
        CAPTURE(wandered);
        CAPTURE(shifted);
        CHECK(shifted > 0.5 * o.wander);
        CHECK(shifted <= 1.4 * o.wander + 1e-9);
        CHECK(wandered <= moved + 1.4 * o.wander + 1e-9);
        CHECK(render::crack_curves(s.pieces, o)[0].uv == wandering[0].uv);
        o.seed = 2;
        CHECK(render::crack_curves(s.pieces, o)[0].uv != wandering[0].uv);
    }

    TEST_CASE("crack curves: turning spreads along the paths, not into kinks at the element-length vertices (the "
              "simulated polylines as the failing control)") {
        for (const std::string name : {"mud", "bark", "fruit"}) {
            CAPTURE(name);
            // (Fruit without its tip sub-model: 1.6 s instead of 4.5; the paths' smoothing is tested.)
            std::vector<std::string> keys{"simulation.elements=2000"};
            if (name == "fruit") keys.emplace_back("simulation.tip_submodel=0");
            const Simulated s = simulate(name, keys);
            render::CurveOptions o;
            o.metres_per_px = s.pieces.tile_size.y() / 2048;
            std::vector<std::vector<Vec2>> chains, curves;
            for (const post::CrackChain& c : s.pieces.chains)
                chains.push_back(c.uv);
            for (const render::CrackCurve& c : render::crack_curves(s.pieces, o))
                curves.push_back(c.uv);
            // Turning within a step of a simulated vertex, on paths resampled every 3 px at 2048² (a
            // kink registers at the sample before or after it).
            const double step = 3 * o.metres_per_px, window = step;
            const double kinked = vertex_turning_share(s.pieces, chains, chains, step, window);
            const double smooth = vertex_turning_share(s.pieces, curves, chains, step, window);
            // Spread evenly, the share is about the windows' share of the length.
            const double spread = 2 * window / s.pieces.element_size;
            CAPTURE(kinked);
            CAPTURE(smooth);
            CAPTURE(spread);
            CHECK(kinked > 0.9); // the control: the polylines turn at their vertices only
            CHECK(smooth < 2 * spread);
        }
    }

    TEST_CASE("bake (grooves = curves): no faceted walls within 6 px of the cracks (crack pixels counted) at 2048², "
              "mud on a plane, bark on a cylinder and fruit on a sphere") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        for (const std::string name : {"mud", "bark", "fruit"}) {
            CAPTURE(name);
            // Mud's pattern at a quarter of its elements (its run is 11× bark's): longer straight
            // crack segments, the harder case for facets at their vertices.
            std::vector<std::string> keys{"bake.grooves=\"curves\"", "bake.fibre_depth=0", "bake.flake_depth=0",
                                          "bake.grit_depth=0", "bake.size=2048"};
            if (name == "mud") keys.emplace_back("simulation.elements=2500");
            // Fruit at a quarter of its 13963 and without its tip sub-model (its run would be 30 s;
            // 2.2 s so): the grooves' shape is tested here, not the pattern.
            if (name == "fruit") keys.insert(keys.end(), {"simulation.elements=3500", "simulation.tip_submodel=0"});
            const Simulated s = simulate(name, keys);
            const render::BakeOptions bo = app::bake_options(s.preset, s.pieces);
            REQUIRE(bo.relief.curves);
            // The raster bake of the same maps: mud 128°, bark 58°, fruit 143° (docs/user-guide.md,
            // "Crack grooves").
            const render::TextureSet set = render::bake(s.pieces, bo, *gl);
            const double p99 = near_crack_p99(set);
            CAPTURE(p99);
            CHECK(p99 <= 10.0);
            // No steps: where blended profiles did not reach their own depth, the floor fillet began
            // with a jump (stop 48's code: mud 442, bark 4708 such pixels, up to 0.7 mm).
            // Nor where a curve comes back beside itself: a join that kept one point per curve let
            // a pixel's nearest point jump between a chain's young, shallow end and its deep middle
            // reached through junctions (bark: 328 step pixels, cliffs of up to 12 mm; with a key per
            // curve part, render/groove_scan.hpp, 7 of at most 0.3 mm).
            const int jumps = steps(set);
            CAPTURE(jumps);
            CHECK(jumps <= 100);
        }
    }

    TEST_CASE("bake (grooves = curves): no faceted walls within 6 px of the cracks at 4096²'s pixel size (mud on a "
              "plane, bark on a cylinder)") {
        // The issue asks the same at 4096². A tile half as wide and high at 2048², with the shapes
        // sized for 1024 px across it, has the pixel size and the groove shapes in metres of the
        // full tile at 4096² (bake.shape_size 2048), at a quarter of the cost; the pattern is the
        // preset's at its own element density. Bark's cylinder is then half as wide round.
        // Measured 2026-12-06: mud 5.6°, bark 3.4° (by hand on full tiles at 4096², stop 44: mud 6.5°,
        // bark 4.1°, fruit 8.0°).
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        for (const std::string name : {"mud", "bark"}) {
            CAPTURE(name);
            const std::vector<double> size = test::load(name).numbers("surface.size");
            const Simulated s = simulate(
                name, {"surface.size=[" + std::to_string(size[0] / 2) + ", " + std::to_string(size[1] / 2) + "]",
                       "simulation.tip_submodel=0", "bake.grooves=\"curves\"", "bake.fibre_depth=0",
                       "bake.flake_depth=0", "bake.grit_depth=0", "bake.size=2048", "bake.shape_size=1024"});
            const double p99 = near_crack_p99(render::bake(s.pieces, app::bake_options(s.preset, s.pieces), *gl));
            CAPTURE(p99);
            CHECK(p99 <= 10.0);
        }
    }

    TEST_CASE("bake (grooves = curves): the grooves have the same shape in metres at every map size (fillets sized "
              "per pixel of each map as the failing control)") {
        // Measured on mud, seed 1, 2000 elements (2026-12-06): the 512-px height map against the
        // 1024-px one averaged 2 × 2, mean difference 32 µm (0.3 % of the 11.6 mm range); with the
        // shapes sized per pixel of each map (bake.shape_size = the map's size, as before the key
        // existed) 1.7 mm, and the 512-px map's range shrinks to 7.9 mm (its fillets are 4× longer).
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        const Simulated s = simulate("mud", {"simulation.elements=2000", "bake.grooves=\"curves\"",
                                             "bake.fibre_depth=0", "bake.flake_depth=0", "bake.grit_depth=0"});
        auto heights = [&](int size, int shape_size) {
            render::BakeOptions bo = app::bake_options(s.preset, s.pieces);
            bo.width = bo.height = size;
            bo.relief.shape_size = shape_size;
            return render::bake(s.pieces, bo, *gl).height;
        };
        auto mean_difference = [&](int shape_small, int shape_large) {
            const std::vector<float> small = heights(512, shape_small), large = heights(1024, shape_large);
            double sum = 0;
            for (int y = 0; y < 512; ++y)
                for (int x = 0; x < 512; ++x) {
                    auto at = [&](int xx, int yy) { return double(large[std::size_t(yy) * 1024 + std::size_t(xx)]); };
                    const double mean =
                        0.25
                        * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
                    sum += std::abs(double(small[std::size_t(y) * 512 + std::size_t(x)]) - mean);
                }
            return sum / (512.0 * 512.0);
        };
        const std::vector<float> reference = heights(1024, 2048);
        const double depth = *std::max_element(reference.begin(), reference.end());
        const double same = mean_difference(2048, 2048), per_pixel = mean_difference(512, 1024);
        MESSAGE("mean height difference 512 vs 1024 px: " << 1e6 * same << " µm with the shapes sized for 2048 px, "
                                                          << 1e6 * per_pixel << " µm sized per pixel of each map ("
                                                          << 1e6 * depth << " µm range)");
        CHECK(same < 0.01 * depth);
        CHECK(per_pixel > 0.05 * depth);
    }

    TEST_CASE("bake (grooves = curves): the crack cores in the Mask cut the map into the simulated pieces, no more and "
              "no fewer, meeting at the same junctions (plane and cylinder)") {
        // Topology kept (issue 35): the smoothed, wandering curves neither join two pieces (a gap in a
        // crack's core) nor cut off islands (two cores that nearly touch). The core is the groove's
        // floor, where the Mask is 1 (≥ 0.995). Measured on mud, seed 1, 2000 elements at 1024²:
        // 277 pieces, 277 regions at ≥ 0.995 and at 1.0; lower thresholds cut the lips' shoulders
        // instead (0.98: 280, three 1-px islands on the 0.976-0.98 shoulder; 0.9: 300; 0.5: 271).
        // The raster bake of the same pattern: 280 at ≥ 0.995 (its lip lines break into islands).
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        for (const std::string kind : {"plane", "cylinder"}) {
            CAPTURE(kind);
            const Simulated s =
                simulate("mud", {"surface.kind=\"" + kind + "\"", "simulation.elements=2000",
                                 "simulation.tip_submodel=0", "bake.grooves=\"curves\"", "bake.size=1024"});
            const render::BakeOptions bo = app::bake_options(s.preset, s.pieces);
            const render::TextureSet set = render::bake(s.pieces, bo, *gl);
            const int pieces = s.pieces.fragments;
            const int regions = mask_regions(set, 0.995f);
            MESSAGE(kind << ": " << pieces << " pieces, " << regions << " regions in the Mask's cores");
            REQUIRE(pieces > 50);
            CHECK(std::abs(regions - pieces) <= std::max(1, pieces / 100));
            // Junctions (measured 2026-12-06, seed 1: plane 554 in the Mask and 554 in the ID map, the
            // raster bake's Mask 560; cylinder 520 and 520).
            // Junctions: where three or more of the Mask's regions meet, against where three or more
            // of the simulated pieces meet in the ID map (rendered from the pieces' own geometry,
            // not from the curves). The simulation's statistic counts only nodes of degree 3 of its
            // crack graph (a node where four pieces meet counts 0 there, 2 here; a crack ending
            // inside a piece counts 1 there, 0 here), so it is reported beside them.
            std::vector<int> in_mask, in_id;
            test::label_regions(
                set.width, set.height_px, [&](std::size_t i) { return set.mask[i] < 0.995f; },
                [](std::size_t, std::size_t) { return true; }, in_mask);
            auto colour = [&](std::size_t i) {
                return (int(set.id[3 * i]) << 16) | (int(set.id[3 * i + 1]) << 8) | int(set.id[3 * i + 2]);
            };
            // A piece's pixels: its colour, away from its antialiased edge (all four neighbours alike).
            auto interior = [&](std::size_t i) {
                const int w = set.width, h = set.height_px, x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
                for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
                    if (colour(std::size_t((y + dy + h) % h) * std::size_t(w) + std::size_t((x + dx + w) % w))
                        != colour(i))
                        return false;
                return colour(i) != 0;
            };
            test::label_regions(
                set.width, set.height_px, interior,
                [&](std::size_t i, std::size_t j) { return colour(i) == colour(j); }, in_id);
            // The ID map's MSAA resolve leaves specks of a piece's colour along the crack floors: only
            // the pieces' main regions count.
            std::vector<int> size(std::size_t(*std::max_element(in_id.begin(), in_id.end()) + 1), 0);
            for (const int l : in_id)
                if (l >= 0) ++size[std::size_t(l)];
            for (int& l : in_id)
                if (l >= 0 && size[std::size_t(l)] < 64) l = -1;
            const Junctions from_mask = region_junctions(set.width, set.height_px, in_mask);
            const Junctions from_pieces = region_junctions(set.width, set.height_px, in_id);
            MESSAGE(kind << ": " << from_mask.count << " junctions in the Mask, " << from_pieces.count
                         << " in the pieces' ID map (" << s.run.statistics.junctions
                         << " nodes of degree 3 in the simulated crack graph); T share " << from_mask.t_share() << " ("
                         << from_mask.t << " T, " << from_mask.y << " Y of " << from_mask.classified << ") against "
                         << from_pieces.t_share() << " (" << from_pieces.t << " T, " << from_pieces.y << " Y of "
                         << from_pieces.classified << ")");
            REQUIRE(from_pieces.count > 50);
            // T stays T, Y stays Y: each junction's largest angle between its branches, matched
            // junction by junction (branches followed 3-10 mm). Measured (seed 1), plane / cylinder:
            // the curves' Mask differs from the pieces by a median 4.1° / 4.8° (p90 12.7° / 14.5°), and
            // on average it is 3.2° / 2.9° smaller (T's close up towards Y's): T share 0.70 / 0.73
            // against the pieces' 0.75 / 0.76. The raster bake, drawn from the same polylines as the
            // ID map, differs by 0.2° (p90 4°), +0.5° on average. Until 2026-12-07 the chains' nodes
            // were the mean of their pieces' corners: a stem ending on a bar at a hanging node put the
            // bar's chain on its near lip (median 5.4° / 6.2°, on average −5.1° / −5.3°, T share 0.68 /
            // 0.71; post/crack_network.cpp now places a node where the pieces are equally far). How what
            // is left builds up, each stage read the same way: the chains drawn as lines −1.2°, the
            // smoothed curves drawn as lines −2.2° (Chaikin's corner cutting reaches into the 3-10 mm
            // the branches are read over), the Mask −3.2°; the join's rounding and the profiles' blending change it by
            // < 0.3°. A known miss of issue 35 (it asks for the T share within 1 %), reported and bounded here.
            const AngleChange change = largest_angle_change(from_pieces, from_mask, set.width, set.height_px);
            MESSAGE(kind << ": largest angle at junctions changes by a median " << change.median << "° (p90 "
                         << change.p90 << "°, on average " << change.mean << "°) from the pieces to the Mask");
            CHECK(change.mean > -4.0);
            // Read at an element's length (reach 40 px = 19.5 mm, mud's elements here ~17 mm) the
            // element-scale kinks the curves round off no longer decide the branch directions: the
            // shift is −1.57° / −1.26° (plane / cylinder), T share 0.56 / 0.60 against the ID map's
            // 0.62 / 0.64. Both rulers depend on where the branches are read far more than they
            // differ from each other: the ID map's T share falls 0.75 → 0.62 from reach 20 to 40 px,
            // and the simulation's own statistic (first segments at degree-3 nodes of its crack
            // graph) is 0.53 / 0.55. At ~330 classified junctions a map, T share has a binomial
            // spread of ±0.025; the 1 % is below what one map can resolve.
            const Junctions mask_far = region_junctions(set.width, set.height_px, in_mask, 40);
            const Junctions pieces_far = region_junctions(set.width, set.height_px, in_id, 40);
            const AngleChange change_far = largest_angle_change(pieces_far, mask_far, set.width, set.height_px);
            MESSAGE(kind << ": at 40 px, T share " << mask_far.t_share() << " against " << pieces_far.t_share()
                         << " (the simulation's " << s.run.statistics.t_junction_fraction
                         << "); largest angle changes on average by " << change_far.mean << "°");
            CHECK(change_far.mean > -2.5);
            CHECK(std::abs(from_mask.count - from_pieces.count) <= std::max(1, from_pieces.count / 100));
            if (kind != "plane") continue;
            // The failing control: the raster bake's Mask, whose lip lines break into islands.
            render::BakeOptions raster = bo;
            raster.relief.curves = false;
            const render::TextureSet control = render::bake(s.pieces, raster, *gl);
            std::vector<int> in_control;
            test::label_regions(
                control.width, control.height_px, [&](std::size_t i) { return control.mask[i] < 0.995f; },
                [](std::size_t, std::size_t) { return true; }, in_control);
            const Junctions from_control = region_junctions(control.width, control.height_px, in_control);
            const AngleChange control_change =
                largest_angle_change(from_pieces, from_control, set.width, set.height_px);
            MESSAGE("control (raster grooves): largest angle changes by a median "
                    << control_change.median << "° (p90 " << control_change.p90 << "°, on average "
                    << control_change.mean << "°)");
            CHECK(control_change.median <= 1.0);
            MESSAGE("control (raster grooves): " << from_control.count << " junctions in the Mask, T share "
                                                 << from_control.t_share());
            CHECK(std::abs(from_control.count - from_pieces.count) > std::max(1, from_pieces.count / 100));
        }
    }
}
