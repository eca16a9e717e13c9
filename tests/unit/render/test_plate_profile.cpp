// Plate profiles of the curves bake (issue 35): drying mud plates are flat topped, not domes
// rounding down from their middles to their rims.
#include "app/run/options.hpp"
#include "render/bake.hpp"
#include "support/gl_support.hpp"
#include "support/presets.hpp"
#include "support/regions.hpp"
#include "support/simulated.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace crackle;

namespace {

struct PlateProfile {
    int plates = 0;
    double low_share = 0; ///< median over plates: share of the plate below 80 % of its top
    double rim_lift = 0;  ///< median over plates: (rim − centre) / top
};

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    const auto k = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

double percentile(std::vector<double> v, double q) {
    const auto k = static_cast<std::size_t>(q * double(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

/// The plates are the connected regions (4-neighbours, periodic) of one piece's ID outside the
/// Mask (< 0.5), of at least 400 pixels. A plate's middle is its part farther than 3 × rim_px from
/// the Mask, its top the 95th percentile of the middle's heights (so that a rim that curl lifts
/// does not count as the top: a cupped plate is not a dome).
PlateProfile plate_profile(const render::TextureSet& set, int rim_px) {
    const int w = set.width, h = set.height_px;
    const std::size_t n = set.pixels();
    // Distance in pixels to the Mask (two-pass chamfer, periodic approximations ignored at the
    // seams: the plates measured there are few).
    std::vector<int> dist(n, 1 << 20);
    for (std::size_t i = 0; i < n; ++i)
        if (set.mask[i] >= 0.5f) dist[i] = 0;
    for (int pass = 0; pass < 2; ++pass)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const int xx = pass ? w - 1 - x : x, yy = pass ? h - 1 - y : y, s = pass ? 1 : -1;
                auto& d = dist[std::size_t(yy) * std::size_t(w) + std::size_t(xx)];
                if (xx + s >= 0 && xx + s < w)
                    d = std::min(d, dist[std::size_t(yy) * std::size_t(w) + std::size_t(xx + s)] + 1);
                if (yy + s >= 0 && yy + s < h)
                    d = std::min(d, dist[std::size_t(yy + s) * std::size_t(w) + std::size_t(xx)] + 1);
            }
    PlateProfile out;
    std::vector<double> shares;
    auto same = [&](std::size_t i, std::size_t j) {
        return set.id[3 * i] == set.id[3 * j] && set.id[3 * i + 1] == set.id[3 * j + 1]
               && set.id[3 * i + 2] == set.id[3 * j + 2];
    };
    std::vector<int> label;
    const int regions = test::label_regions(
        w, h, [&](std::size_t i) { return set.mask[i] < 0.5f; }, same, label);
    std::vector<std::vector<std::size_t>> plates(static_cast<std::size_t>(regions));
    for (std::size_t i = 0; i < n; ++i)
        if (label[i] >= 0) plates[static_cast<std::size_t>(label[i])].push_back(i);
    std::vector<double> lifts;
    for (const std::vector<std::size_t>& members : plates) {
        if (members.size() < 400) continue;
        // A plate's top may slope with the layer (mud/thickness-gradient thickens 1 → 4 cm along
        // v): its heights are taken against the plane fitted to its middle (least squares; the
        // pixels unwrapped across the seams from the plate's first), its mean kept.
        auto at = [&](std::size_t i) {
            const double x0 = double(members.front() % std::size_t(w)), y0 = double(members.front() / std::size_t(w));
            double x = double(i % std::size_t(w)) - x0, y = double(i / std::size_t(w)) - y0;
            x -= w * std::round(x / w), y -= h * std::round(y / h);
            return Eigen::Vector3d(1.0, x, y);
        };
        Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
        Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
        for (const std::size_t i : members)
            if (dist[i] > 3 * rim_px) normal += at(i) * at(i).transpose(), rhs += at(i) * double(set.height[i]);
        Eigen::Vector3d plane = normal.ldlt().solve(rhs);
        if (!plane.allFinite()) plane.setZero();
        std::vector<double> all, middle, depths;
        for (const std::size_t i : members) {
            const double height = set.height[i] - plane.y() * at(i).y() - plane.z() * at(i).z();
            all.push_back(height);
            depths.push_back(dist[i]);
            if (dist[i] > 3 * rim_px) middle.push_back(height);
        }
        if (middle.size() < 10) continue;
        const double top = percentile(middle, 0.95);
        if (top <= 0) continue;
        shares.push_back(double(std::count_if(all.begin(), all.end(), [&](double v) { return v < 0.8 * top; }))
                         / double(all.size()));
        // The rim: the highest of the rings 2 px wide within 30 px of the Mask (median height of
        // each); the centre: the median height of the plate's innermost fifth.
        const double inner = percentile(depths, 0.8);
        std::vector<double> centre;
        std::array<std::vector<double>, 15> rings;
        for (const std::size_t i : members) {
            if (dist[i] >= inner) centre.push_back(set.height[i]);
            if (dist[i] < 30) rings[static_cast<std::size_t>(dist[i] / 2)].push_back(set.height[i]);
        }
        double rim = -1e300;
        for (const std::vector<double>& ring : rings)
            if (ring.size() >= 10) rim = std::max(rim, median(ring));
        if (rim > -1e300 && !centre.empty()) lifts.push_back((rim - median(centre)) / top);
    }
    out.plates = static_cast<int>(shares.size());
    out.low_share = median(shares);
    out.rim_lift = median(lifts);
    return out;
}

/// The plate profile of a quarter of `preset`'s tile at 1024²: the preset's own element density
/// and the pixel size (and groove shapes: bake.shape_size) of its full tile at 2048², at a quarter
/// of the cost. Micro-relief off; `extra` overrides come last.
PlateProfile quarter_tile_profile(render::GlContext& gl, const std::string& preset,
                                  const std::vector<std::string>& extra) {
    const std::vector<double> size = test::load(preset).numbers("surface.size");
    std::vector<std::string> overrides{"surface.size=[" + std::to_string(size[0] / 2) + ", "
                                           + std::to_string(size[1] / 2) + "]",
                                       "simulation.tip_submodel=0",
                                       "bake.fibre_depth=0",
                                       "bake.flake_depth=0",
                                       "bake.grit_depth=0",
                                       "bake.size=1024",
                                       "bake.shape_size=1024"};
    overrides.insert(overrides.end(), extra.begin(), extra.end());
    const test::Simulated s = test::simulate(preset, overrides);
    return plate_profile(render::bake(s.pieces, app::bake_options(s.preset, s.pieces), gl), 8);
}

} // namespace

TEST_SUITE("render") {
    TEST_CASE("bake (grooves = curves): the default mud's plates are flat topped, not domes (a wide rounding as the "
              "failing control), and cupped where curl lifts their rims") {
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        auto profile = [&](std::vector<std::string> extra) {
            extra.insert(extra.begin(), "bake.grooves=\"curves\"");
            return quarter_tile_profile(*gl, "mud", extra);
        };
        const PlateProfile flat = profile({});
        MESSAGE("mud: " << flat.plates << " plates, " << 100 * flat.low_share
                        << " % of a plate below 80 % of its top, rim " << 100 * flat.rim_lift
                        << " % of the top above the centre");
        REQUIRE(flat.plates >= 30);
        CHECK(flat.low_share <= 0.15);
        // With curl on, the rims stand higher than the centres (the plates cup); without it they do
        // not (the control: the highest ring of a flat plate is above its centre only by noise).
        const PlateProfile uncurled = profile({"post.curl=0"});
        MESSAGE("post.curl = 0: rim " << 100 * uncurled.rim_lift << " % of the top above the centre");
        CHECK(flat.rim_lift >= 0.02);
        CHECK(uncurled.rim_lift <= 0.01);
        // Control: plates rounded over 3 cm from their rims are domes.
        const PlateProfile domed = profile({"bake.crack_width=0.03", "bake.crack_shape=0"});
        MESSAGE("rounded over 3 cm: " << 100 * domed.low_share << " %");
        CHECK(domed.low_share > 0.3);
    }

    TEST_CASE("bake: mud's variants' plates are flat topped with their own grooves (issue 35: mud and its "
              "variants)") {
        // Each with the grooves its preset sets: curves for mud and thin, thick, perturbed and
        // dry-riverbed; raster for craquelure, curling-flakes, peeling-paint and
        // thickness-gradient (their narrow or curled plates would be widened into troughs by the
        // curves' fillets: full tiles at 2048² with curves, 44.8 %, 17.0 %, 12.1 % and 19.5 %).
        // thickness-gradient's plates slope with its layer (1 -> 4 cm): measured against the plane of
        // each plate's middle, 3.9 % (against the flat top it was 21.6 %). peeling-paint: the next test.
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        for (const std::string preset : {"mud/thin", "mud/thick", "mud/perturbed", "mud/dry-riverbed", "mud/craquelure",
                                         "mud/curling-flakes", "mud/thickness-gradient"}) {
            CAPTURE(preset);
            const PlateProfile p = quarter_tile_profile(*gl, preset, {});
            MESSAGE(preset << ": " << p.plates << " plates, " << 100 * p.low_share << " % below 80 % of the top");
            REQUIRE(p.plates >= 10);
            CHECK(p.low_share <= 0.15);
        }
    }

    TEST_CASE("bake: peeling paint's flakes, their rims curled three film thicknesses, are cups, not domes: the rims "
              "stand above the centres, and without curl the flakes are flat topped") {
        // With its curl its share below 80 % of the top is above 15 % (2026-12-07: 16.0 %), but the
        // low pixels are the cups' middles, not the rims: the rims stand 32 % of the top above the
        // centres. A dome's rim is below its centre.
        auto gl = test::gl_context_or_skip();
        if (!gl) return;
        const std::string preset = "mud/peeling-paint";
        const PlateProfile cupped = quarter_tile_profile(*gl, preset, {});
        const PlateProfile uncurled = quarter_tile_profile(*gl, preset, {"post.curl=0"});
        MESSAGE(preset << ": " << cupped.plates << " plates, " << 100 * cupped.low_share
                       << " % below 80 % of the top, rim " << 100 * cupped.rim_lift
                       << " % of the top above the centre; without curl " << 100 * uncurled.low_share << " % and "
                       << 100 * uncurled.rim_lift << " %");
        REQUIRE(cupped.plates >= 10);
        CHECK(cupped.rim_lift >= 0.02);
        CHECK(uncurled.low_share <= 0.15);
        CHECK(uncurled.rim_lift < 0.02);
    }
}
