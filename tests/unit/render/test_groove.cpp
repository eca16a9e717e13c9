// Grooves from crack curves (render/groove, issue 35), on curves drawn by hand: a groove's profile
// is monotone, reaches its depth on the floor and turns its slope by a bounded angle per pixel;
// the scan finds what an exhaustive scan finds, the curl's lift on its grid matches every pixel's;
// where cracks meet, the height has no crease. The bakes of the presets: test_groove_bake.cpp.
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

} // namespace

TEST_SUITE("render") {
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

    TEST_CASE("grooves: a curve that comes back beside itself (a hairpin) has no crease where its nearest point "
              "crosses from one arm to the other, and away from the bend joins its arms as two curves would (a plane "
              "and a sphere's map)") {
        const FlatTile tile;
        const PixelGrid sphere = sphere_grid();
        for (const PixelGrid& g : {tile.g, sphere}) {
            CAPTURE(g.wrap_v);
            const std::vector<float> tops(g.pixels(), static_cast<float>(tile.top));
            const render::GrooveOptions o = options(g);
            // Two arms 5 mm apart, joined by a half circle of 2.5 mm radius at u = 0.7: the grooves
            // overlap between them. The arms' profiles differ (weights 1 and 0.4, depths 6.4 and 4 mm),
            // as a chain's young, shallow end beside its older middle does.
            std::vector<Vec2> pts;
            std::vector<float> weight;
            for (int k = 0; k <= 30; ++k)
                pts.emplace_back(0.1 + 0.02 * k, 0.4), weight.push_back(1.0f);
            for (int k = 1; k < 20; ++k) {
                const double a = PI * k / 20 - 0.5 * PI;
                pts.emplace_back(0.7 + 0.05 * std::cos(a), 0.45 + 0.05 * std::sin(a));
                weight.push_back(static_cast<float>(1.0 - 0.6 * k / 20));
            }
            for (int k = 30; k >= 0; --k)
                pts.emplace_back(0.1 + 0.02 * k, 0.5), weight.push_back(0.4f);
            render::CrackCurve hairpin = curve(pts, 0.0004f);
            hairpin.weight = weight;
            // The same arms as two curves, cut at the apex.
            const std::size_t apex = 31 + 9;
            auto part = [&](std::size_t from, std::size_t to) {
                render::CrackCurve c = curve({pts.begin() + from, pts.begin() + to + 1}, 0.0004f);
                c.weight.assign(weight.begin() + from, weight.begin() + to + 1);
                return c;
            };
            const render::GrooveField one = render::groove_field(g, {hairpin}, tops, o);
            const render::GrooveField two =
                render::groove_field(g, {part(0, apex), part(apex, pts.size() - 1)}, tops, o);
            // No crease: away from the apex (where the arms' grooves meet in a cone) the normals turn
            // between neighbours by no more than those of the two curves, whose grooves meet in a crest
            // rounded by the join (the join that kept one point per curve: 77.7 deg against 48.6).
            auto sharpest = [&](const render::GrooveField& f) {
                const std::vector<float> n = render::normals_from_height(g, heights(f, tile.top));
                double turn = 0;
                for (int y = 0; y + 1 < g.height; ++y)
                    for (int x = 0; x + 1 < g.width; ++x) {
                        if ((x + 0.5) / g.width < 0.15 || (x + 0.5) / g.width > 0.6) continue;
                        const std::size_t i = g.index(x, y);
                        for (const std::size_t j : {g.index(x + 1, y), g.index(x, y + 1)}) {
                            const double dot =
                                n[3 * i] * n[3 * j] + n[3 * i + 1] * n[3 * j + 1] + n[3 * i + 2] * n[3 * j + 2];
                            turn = std::max(turn, std::acos(std::clamp(dot, -1.0, 1.0)) * RAD_TO_DEG);
                        }
                    }
                return turn;
            };
            const double turn_one = sharpest(one), turn_two = sharpest(two);
            CAPTURE(turn_one);
            CAPTURE(turn_two);
            CHECK(turn_one <= turn_two + 1.0);
            // Where the arms are farther apart along the curve than 3.6x their distances from the pixel
            // (here from 15 mm off the apex), between and around them: the heights of two curves.
            double worst = 0, between = 0;
            for (int y = 0; y < g.height; ++y)
                for (int x = 0; x < g.width; ++x) {
                    const double u = (x + 0.5) / g.width, v = 1.0 - (y + 0.5) / g.height;
                    if (u < 0.2 || u > 0.4 || v < 0.33 || v > 0.57) continue;
                    const std::size_t i = g.index(x, y);
                    worst = std::max(worst, std::abs(double(one.drop[i]) - two.drop[i]));
                    if (std::abs(v - 0.45) < 0.01) between = std::max(between, double(two.drop[i]));
                }
            CAPTURE(worst);
            CAPTURE(between);
            CHECK(between > 0.05 * tile.top); // the grooves do overlap between the arms
            CHECK(worst <= 1e-5 * tile.top);  // (the float profiles blended in another order: 0.02 µm)
        }
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
}
