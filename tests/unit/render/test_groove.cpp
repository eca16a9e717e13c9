// Grooves from crack curves (render/crack_curves, render/groove, issue 35): the curves keep the
// simulated chains' ends and stay within a quarter element (plus the wander) of them; a groove's
// profile is monotone, reaches its depth on the floor and turns its slope by a bounded angle
// per pixel; where cracks meet, the height has no crease; baked bark and fruit at 2048² show no
// faceted walls next to the cracks; the Mask keeps the pieces and the junctions where they meet.
#include "app/options.hpp"
#include "app/pipeline.hpp"
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

PixelGrid plane_grid(int n, double metres) {
    PixelGrid g;
    g.width = g.height = n;
    g.metres_v = metres / n;
    g.wrap_v = true;
    g.metres_u.assign(static_cast<std::size_t>(n), metres / n);
    return g;
}

/// Rows of a sphere's map (10 × 5 cm, 256 × 128 px), the metres per pixel along u shrinking with the
/// latitude's cosine (render::metres_per_u).
PixelGrid sphere_grid() {
    PixelGrid g;
    g.width = 256;
    g.height = 128;
    g.wrap_v = false;
    g.metres_v = 0.05 / g.height;
    for (int y = 0; y < g.height; ++y) {
        const double v = 1.0 - (y + 0.5) / g.height;
        g.metres_u.push_back(0.1 * std::max(std::cos(PI * (v - 0.5)), 1e-3) / g.width);
    }
    return g;
}

/// A curve through texture points, with uniform attributes.
render::CrackCurve curve(const std::vector<Vec2>& uv, float opening, float weight = 1.0f) {
    render::CrackCurve c;
    c.uv = uv;
    c.weight.assign(uv.size(), weight);
    c.age.assign(uv.size(), 1.0f);
    c.opening.assign(uv.size(), opening);
    c.taper.assign(uv.size(), 1.0f);
    return c;
}

/// A 5 cm tile of 256² pixels, its plates 8 mm high everywhere.
struct FlatTile {
    PixelGrid g = plane_grid(256, 0.05);
    double top = 0.008;
    std::vector<float> tops = std::vector<float>(g.pixels(), static_cast<float>(top));
};

/// Largest angle (degrees) between the normals of neighbouring pixels, over the whole grid.
double largest_turn(const PixelGrid& g, const std::vector<float>& height, int* at_x = nullptr, int* at_y = nullptr) {
    const std::vector<float> n = render::normals_from_height(g, height);
    double worst = 0;
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            const Vec3 a(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
            for (const std::size_t j : {g.index((x + 1) % g.width, y), g.index(x, (y + 1) % g.height)}) {
                const Vec3 b(n[3 * j], n[3 * j + 1], n[3 * j + 2]);
                const double angle = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * RAD_TO_DEG;
                if (angle > worst && at_x) *at_x = x, *at_y = y;
                worst = std::max(worst, angle);
            }
        }
    return worst;
}

std::vector<float> heights(const render::GrooveField& f, double top) {
    std::vector<float> h(f.drop.size());
    for (std::size_t i = 0; i < h.size(); ++i)
        h[i] = static_cast<float>(top - f.drop[i]);
    return h;
}

render::GrooveOptions options(const PixelGrid& g) {
    render::GrooveOptions o;
    o.crack_width = 0.006;
    o.crack_depth = 0.8;
    o.crack_shape = 0.3;
    o.rounding = 0.001;
    o.pixel = g.metres_v;
    o.join_radius = 3 * g.metres_v;
    o.smoothing_px = 4;
    return o;
}

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
/// of `b` within 4 px; periodic): the median and the 90th percentile of |Δ| in degrees.
std::pair<double, double> largest_angle_change(const Junctions& a, const Junctions& b, int w, int h) {
    std::vector<double> diff;
    for (const auto& p : a.at) {
        double best = 1e300, angle = 0;
        for (const auto& q : b.at) {
            double dx = std::abs(q[0] - p[0]), dy = std::abs(q[1] - p[1]);
            dx = std::min(dx, w - dx), dy = std::min(dy, h - dy);
            if (std::hypot(dx, dy) < best) best = std::hypot(dx, dy), angle = q[2];
        }
        if (best <= 4) diff.push_back(std::abs(angle - p[2]));
    }
    REQUIRE(diff.size() * 10 >= a.at.size() * 9); // nearly every junction found again
    std::sort(diff.begin(), diff.end());
    return {diff[diff.size() / 2], diff[diff.size() * 9 / 10]};
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
            const Simulated s = simulate(name, {"simulation.elements=2000"});
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

    TEST_CASE("grooves: a straight crack's profile falls monotonically to its floor, reaches its depth there, ends at "
              "its reach, and turns its slope by at most 10 degrees per pixel") {
        const PixelGrid g = plane_grid(256, 0.05);
        const double top = 0.008;
        const std::vector<float> tops(g.pixels(), static_cast<float>(top));
        const render::GrooveOptions o = options(g);
        const std::vector<render::CrackCurve> curves{curve({Vec2(0.5, -0.2), Vec2(0.5, 0.4), Vec2(0.5, 1.2)}, 0.001f)};
        const render::GrooveField f = render::groove_field(g, curves, tops, o);
        const std::vector<float> h = heights(f, top);
        const int y = 100, mid = 128; // the crack at u = 0.5 is between pixels 127 and 128
        const double depth = top * 0.8;
        CHECK(f.drop[g.index(mid, y)] == doctest::Approx(depth).epsilon(0.02));
        for (int x = mid; x + 1 < g.width; ++x)
            CHECK(h[g.index(x + 1, y)] >= h[g.index(x, y)] - 1e-9);
        // Beyond the floor and the widest reach the groove solves for (a few fillets), the plate.
        CHECK(f.drop[g.index(mid + 110, y)] == 0.0f);
        CHECK(f.drop[g.index(mid - 111, y)] == 0.0f);
        // Symmetric about the crack, the same on every row.
        CHECK(f.drop[g.index(mid + 10, y)] == doctest::Approx(f.drop[g.index(mid - 11, y)]).epsilon(1e-3));
        CHECK(f.drop[g.index(mid + 10, 7)] == doctest::Approx(f.drop[g.index(mid + 10, y)]).epsilon(1e-4));
        const double turn = largest_turn(g, h);
        CAPTURE(turn);
        CHECK(turn <= 10.0);
    }

    TEST_CASE("grooves: the scan finds every pixel's nearest curve point, as scanning each segment's whole "
              "neighbourhood does (tight bends, turns past 90°, a loop, a loop round the period, curl on)") {
        const FlatTile tile;
        const PixelGrid& g = tile.g;
        const double top = tile.top;
        const std::vector<float>& tops = tile.tops;
        render::GrooveOptions o = options(g);
        o.curl = 0.3;
        o.curl_reach = 0.01; // the rims' lift reaches 10 mm: every curve scans 51 px each side
        std::vector<render::CrackCurve> curves;
        std::vector<Vec2> bend, zigzag, loop, around;
        for (int k = 0; k <= 60; ++k) { // a bend of 3 mm radius, far tighter than the scan
            const double a = PI * k / 40.0;
            bend.emplace_back(0.3 + 0.06 * std::cos(a), 0.3 + 0.06 * std::sin(a));
        }
        for (int k = 0; k <= 12; ++k) // turns of 90° to 143° at every point
            zigzag.emplace_back(0.55 + 0.02 * k, 0.25 + (k % 2 ? 0.04 : 0.0) + (k % 3 == 0 ? 0.02 : 0.0));
        for (int k = 0; k <= 48; ++k) {
            const double a = 2 * PI * k / 48.0;
            loop.emplace_back(0.7 + 0.1 * std::cos(a), 0.7 + 0.07 * std::sin(2 * a) + 0.02 * std::sin(a));
        }
        loop.back() = loop.front();
        for (int k = 0; k <= 40; ++k) // closes on its image one period on in u
            around.emplace_back(k / 40.0,
                                0.45 + 0.03 * std::sin(2 * PI * k / 40.0) + 0.01 * std::sin(6 * PI * k / 40.0));
        for (const auto* pts : {&bend, &zigzag, &loop, &around})
            curves.push_back(curve(*pts, 0.0004f));
        curves[2].closed = curves[3].closed = true;
        const render::GrooveField f = render::groove_field(g, curves, tops, o);
        render::GrooveOptions all = o;
        all.wedge_margin_px = 1e9;
        const render::GrooveField reference = render::groove_field(g, curves, tops, all);
        double worst = 0, lifted = 0;
        for (std::size_t i = 0; i < g.pixels(); ++i) {
            worst = std::max({worst, std::abs(double(f.drop[i]) - reference.drop[i]),
                              std::abs(double(f.lift[i]) - reference.lift[i]),
                              top * std::abs(double(f.coverage[i]) - reference.coverage[i])});
            lifted = std::max(lifted, double(reference.lift[i]));
        }
        CAPTURE(worst);
        CHECK(lifted > 0.1 * top);
        CHECK(worst <= 1e-6 * top);
    }

    TEST_CASE(
        "grooves: the curl's lift, measured on a grid 4 px apart beyond the grooves and interpolated, is the "
        "lift measured at every pixel (cracks meeting in a T and a Y, a bend), and adds no crease: on a plane and on "
        "a sphere's map (rows shrinking towards the poles)") {
        const PixelGrid sphere = sphere_grid();
        for (const PixelGrid& g : {plane_grid(256, 0.05), sphere}) {
            CAPTURE(g.wrap_v);
            const double top = 0.008;
            const std::vector<float> tops(g.pixels(), static_cast<float>(top));
            render::GrooveOptions o = options(g);
            o.curl = 0.3;
            o.curl_reach = 0.01;             // 51 px from the lip
            o.join_radius = 12 * g.metres_v; // the lift's grid: 4 px (a third of the join radius)
            const Vec2 t0(0.3, 0.3), y0(0.7, 0.7);
            std::vector<render::CrackCurve> curves{
                curve({Vec2(0.05, 0.3), t0, Vec2(0.55, 0.3)}, 0.0008f),
                curve({t0, Vec2(0.3, 0.15), Vec2(0.3, 0.02)}, 0.0008f, 0.8f),
                curve({y0, y0 + 0.15 * Vec2(1, 0)}, 0.0008f),
                curve({y0, y0 + 0.15 * Vec2(-0.5, 0.866)}, 0.0008f, 0.5f),
                curve({y0, y0 + 0.15 * Vec2(-0.5, -0.866)}, 0.0002f),
            };
            std::vector<Vec2> arc;
            for (int k = 0; k <= 40; ++k)
                arc.push_back(Vec2(0.72, 0.05) + 0.16 * Vec2(std::cos(0.5 * PI * k / 40), std::sin(0.5 * PI * k / 40)));
            curves.push_back(curve(arc, 0.0008f));
            auto relief = [&](int step) {
                render::GrooveOptions with = o;
                with.lift_step_px = step;
                const render::GrooveField f = render::groove_field(g, curves, tops, with);
                std::vector<float> h(g.pixels());
                for (std::size_t i = 0; i < h.size(); ++i)
                    h[i] = static_cast<float>(top + f.lift[i] - f.drop[i] * (1.0 + f.lift[i] / top));
                return h;
            };
            const std::vector<float> exact = relief(1), coarse = relief(0);
            // The largest height difference (as a share of the curl's lift) and the 99th percentile of
            // the angle between the normals: the exact field has cone points (the bend's centre, where
            // the whole arc is equally far) that the interpolation rounds over a few pixels.
            auto compare = [&](const std::vector<float>& h) {
                const std::vector<float> n = render::normals_from_height(g, h),
                                         m = render::normals_from_height(g, exact);
                double height = 0;
                std::vector<double> angles;
                for (std::size_t i = 0; i < h.size(); ++i) {
                    height = std::max(height, std::abs(double(h[i]) - exact[i]));
                    const double dot = n[3 * i] * m[3 * i] + n[3 * i + 1] * m[3 * i + 1] + n[3 * i + 2] * m[3 * i + 2];
                    angles.push_back(std::acos(std::clamp(dot, -1.0, 1.0)) * RAD_TO_DEG);
                    if (!g.wrap_v && angles.back() > 3) MESSAGE("row " << i / std::size_t(g.width));
                }
                std::nth_element(angles.begin(), angles.begin() + long(0.99 * double(angles.size())), angles.end());
                return std::pair{height / (o.curl * top), angles[std::size_t(0.99 * double(angles.size()))]};
            };
            const auto [height, angle] = compare(coarse);
            CAPTURE(height);
            CAPTURE(angle);
            CHECK(height <= 0.01);
            CHECK(angle <= 0.5);
            // On the sphere a grid 4 px apart was 2.9 % of the lift and 4° (99th percentile) off:
            // the lift is measured at every pixel there.
            if (!g.wrap_v) CHECK(height == 0.0);
            const double turn = largest_turn(g, coarse), exact_turn = largest_turn(g, exact);
            CAPTURE(turn);
            CAPTURE(exact_turn);
            CHECK(turn <= exact_turn + 0.5);
            // Control: a grid 16 px apart (wider than the join's rounding) is off by more.
            const auto [far_height, far_angle] = compare(relief(16));
            CAPTURE(far_height);
            CAPTURE(far_angle);
            CHECK(far_height > 0.01);
            CHECK(far_angle > 0.5);
        }
    }

    TEST_CASE("grooves: a groove's shape does not depend on how far the curl's lift reaches, and the scan's "
              "simplified curves keep the relief within a few micrometres of every point's") {
        const FlatTile tile;
        const PixelGrid& g = tile.g;
        render::GrooveOptions o = options(g);
        o.curl = 0.3;
        // Cracks close together (their grooves' extents overlap) and dense points, as the
        // smoothing and the wander leave them: a wavy crack of 2000 points, two straight ones.
        std::vector<Vec2> wavy;
        for (int k = 0; k <= 2000; ++k) {
            const double s = k / 2000.0;
            wavy.emplace_back(0.1 + 0.8 * s, 0.5 + 0.02 * std::sin(9 * PI * s) + 0.004 * std::sin(61 * PI * s));
        }
        std::vector<render::CrackCurve> curves{curve(wavy, 0.0006f),
                                               curve({Vec2(0.1, 0.62), Vec2(0.9, 0.62)}, 0.0003f, 0.6f),
                                               curve({Vec2(0.5, 0.62), Vec2(0.5, 0.95)}, 0.0002f, 0.4f)};
        for (std::size_t i = 0; i < curves[0].taper.size(); ++i) // a tapering tip at the wavy crack's end
            curves[0].taper[i] = static_cast<float>(std::min(1.0, (2000.0 - double(i)) / 300.0));
        curves[0].tip_back = true;
        auto field = [&](double reach, double simplify) {
            render::GrooveOptions with = o;
            with.curl_reach = reach;
            with.simplify_px = simplify;
            return render::groove_field(g, curves, tile.tops, with);
        };
        // The curl's reach (5 or 20 mm) moves only the lift: the grooves' profiles join over their
        // own extent, not the lift's.
        const render::GrooveField near = field(0.005, 0.02), far = field(0.02, 0.02);
        CHECK(near.drop == far.drop);
        CHECK(near.coverage == far.coverage);
        CHECK(near.lift != far.lift);
        // Simplified (each curve's points kept where dropping them would move the curve or its
        // profile by more than 0.02 px) against every point kept: within 10 µm along the crack, and
        // within 0.1 mm over the tapering tip's last 30 px (measured: 64 µm; at 4096² the presets' maps
        // are within 16 µm (mud) and 46 µm (bark) of every point's, 99.9 % of pixels within 2.4 µm).
        const render::GrooveField every = field(0.005, 0.0);
        double worst = 0, worst_tip = 0, lifted = 0;
        for (std::size_t i = 0; i < g.pixels(); ++i) {
            const auto h = [&](const render::GrooveField& f) {
                return tile.top + f.lift[i] - f.drop[i] * (1.0 + f.lift[i] / tile.top);
            };
            double& into = int(i % std::size_t(g.width)) < 200 ? worst : worst_tip; // the tip is at x = 230
            into = std::max(into, std::abs(h(near) - h(every)));
            lifted = std::max(lifted, double(every.lift[i]));
        }
        CAPTURE(worst);
        CAPTURE(worst_tip);
        CHECK(lifted > 0.1 * tile.top);
        CHECK(worst <= 1e-5); // of an 8 mm relief on 0.2 mm pixels (measured: 8.6 µm)
        CHECK(worst_tip <= 1e-4);
        CHECK(worst + worst_tip > 0.0); // the points were simplified
    }

    TEST_CASE("grooves: next to a sphere's pole, where a row's scan is wider than the period, every pixel is as "
              "far from the curve as its nearest image") {
        // A curve close to the top pole.
        const PixelGrid g = sphere_grid();
        const std::vector<float> tops(g.pixels(), 0.008f);
        const render::GrooveOptions o = options(g);
        const std::vector<render::CrackCurve> curves{
            curve({Vec2(0.1, 0.96), Vec2(0.45, 0.985), Vec2(0.8, 0.975), Vec2(0.95, 0.99)}, 0.0004f)};
        const render::GrooveField f = render::groove_field(g, curves, tops, o);
        // Each row measured in its own metres, as the bake does; every image of the pixel a period
        // apart along u tried.
        std::vector<Vec2> px;
        for (const Vec2& uv : curves[0].uv)
            px.emplace_back(uv.x() * g.width - 0.5, (1.0 - uv.y()) * g.height - 0.5);
        double worst = 0;
        int checked = 0;
        for (int y = 0; y < 12; ++y) {
            const double mu = g.metres_u[static_cast<std::size_t>(y)], mv = g.metres_v;
            for (int x = 0; x < g.width; ++x) {
                double best = 1e300;
                for (int k = -40; k <= 40; ++k)
                    for (std::size_t i = 0; i + 1 < px.size(); ++i) {
                        const Vec2 a(px[i].x() * mu, px[i].y() * mv), b(px[i + 1].x() * mu, px[i + 1].y() * mv);
                        const Vec2 q((x + k * g.width) * mu, y * mv), ab = b - a;
                        const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
                        best = std::min(best, (q - a - t * ab).norm());
                    }
                if (best > 0.004) continue; // within the groove (its extent is over 6 mm)
                ++checked;
                worst = std::max(worst, std::abs(double(f.distance[g.index(x, y)]) - best));
            }
        }
        CAPTURE(checked);
        CAPTURE(worst);
        CHECK(checked > 2000);
        CHECK(worst <= 1e-6);
    }

    TEST_CASE("grooves: with bake.crack_depth = 0 the simulation sets the depth: an opened crack goes through the "
              "layer, a closed one is cut by the bevel") {
        const FlatTile tile;
        render::GrooveOptions o = options(tile.g);
        o.crack_depth = 0;
        o.bevel = 0.002;
        const int y = 100, mid = 128;
        const auto drop_at_crack = [&](float opening) {
            const std::vector<render::CrackCurve> curves{
                curve({Vec2(0.5, -0.2), Vec2(0.5, 0.4), Vec2(0.5, 1.2)}, opening)};
            return double(render::groove_field(tile.g, curves, tile.tops, o).drop[tile.g.index(mid, y)]);
        };
        // Before this, both were 0: the table-5-2 presets baked with curves showed no cracks at all.
        CHECK(drop_at_crack(0.001f) == doctest::Approx(tile.top).epsilon(0.02));
        CHECK(drop_at_crack(0.0f) == doctest::Approx(o.bevel).epsilon(0.05));
    }

    TEST_CASE("grooves: where cracks meet (a T, a Y) and round a bend, the height has no crease") {
        const PixelGrid g = plane_grid(256, 0.05);
        const double top = 0.008;
        const std::vector<float> tops(g.pixels(), static_cast<float>(top));
        const render::GrooveOptions o = options(g);
        // T: a bar across the tile and a stem ending on it; Y: three arms at 120°; a bend of 90°.
        const Vec2 t0(0.3, 0.3), y0(0.7, 0.7);
        std::vector<render::CrackCurve> curves{
            curve({Vec2(0.05, 0.3), t0, Vec2(0.55, 0.3)}, 0.0008f),
            curve({t0, Vec2(0.3, 0.15), Vec2(0.3, 0.02)}, 0.0008f, 0.8f),
            curve({y0, y0 + 0.15 * Vec2(1, 0)}, 0.0008f),
            curve({y0, y0 + 0.15 * Vec2(-0.5, 0.866)}, 0.0008f),
            curve({y0, y0 + 0.15 * Vec2(-0.5, -0.866)}, 0.0008f),
        };
        // The bend: a quarter circle, as smoothing leaves a corner, of a radius larger than the
        // groove reaches (inside a tighter bend the walls meet in a cone's point: a known limit).
        std::vector<Vec2> arc;
        for (int k = 0; k <= 40; ++k)
            arc.push_back(Vec2(0.72, 0.05) + 0.16 * Vec2(std::cos(0.5 * PI * k / 40), std::sin(0.5 * PI * k / 40)));
        curves.push_back(curve(arc, 0.0008f));
        const render::GrooveField f = render::groove_field(g, curves, tops, o);
        int wx = 0, wy = 0;
        const double turn = largest_turn(g, heights(f, top), &wx, &wy);
        CAPTURE(turn);
        CAPTURE(wx);
        CAPTURE(wy);
        CHECK(turn <= 12.0);
        // Control: the same grooves from the nearest crack alone (no join) crease where two meet.
        render::GrooveOptions hard = o;
        hard.join_radius = 1e-9;
        const double creased = largest_turn(g, heights(render::groove_field(g, curves, tops, hard), top));
        CAPTURE(creased);
        CHECK(creased > 1.5 * turn);
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
            // junction by junction. Measured (seed 1, branches followed 3-10 mm): the curves' Mask
            // differs from the pieces by a median 5.8° on the plane and 6.0° on the cylinder (p90 17°),
            // and its T share is lower (plane 0.67 against 0.75, cylinder 0.71 against 0.76), where the
            // raster bake, drawn from the same polylines as the ID map, differs by 0.2° (p90 4°; T share
            // 0.75). The change fades with the distance from the junction (branches at 2-6 mm: 10°;
            // 5-15 mm: 3.9°; 6-20 mm: 3.6°); it is not the join's rounding (radius 1 or 6 shape pixels:
            // the same) and only partly the curves' smoothing (4.8° without it). A known miss of issue 35,
            // reported here; the check holds the measurement itself to the raster control.
            const auto [median, p90] = largest_angle_change(from_pieces, from_mask, set.width, set.height_px);
            MESSAGE(kind << ": largest angle at junctions changes by a median " << median << "° (p90 " << p90
                         << "°) from the pieces to the Mask");
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
            const auto [control_median, control_p90] =
                largest_angle_change(from_pieces, from_control, set.width, set.height_px);
            MESSAGE("control (raster grooves): largest angle changes by a median " << control_median << "° (p90 "
                                                                                   << control_p90 << "°)");
            CHECK(control_median <= 1.0);
            MESSAGE("control (raster grooves): " << from_control.count << " junctions in the Mask, T share "
                                                 << from_control.t_share());
            CHECK(std::abs(from_control.count - from_pieces.count) > std::max(1, from_pieces.count / 100));
        }
    }
}
