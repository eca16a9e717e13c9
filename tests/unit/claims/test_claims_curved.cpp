// Thesis claims on curved surfaces (fem-split): a growing sphere cracks isotropically, or along
// the latitude circles when it grows faster along Z (Fig. 5.32); a trunk growing around its
// axis opens vertical bark fissures whose spacing follows the bark's thickness and threshold
// (Figs. 5.33-5.34, Table 5.2). And a check of curvature itself: the cylinder's stress, first
// fracture and patterns approach the plane's as the trunk's radius grows.

#include "fracture/fem_split/fem_split.hpp"
#include "support/accuracy.hpp"
#include "support/claims_fixture.hpp"
#include "support/curved_claims.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace crackle;
using test::LayerSpec;

namespace {

double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v)
        s += x;
    return s / double(v.size());
}

// === Sphere (Fig. 5.32)

/// Bands of |latitude| (degrees, both hemispheres): 34 %, 30 %, 22 % and 13 % of the area.
/// Narrower caps hold too few cracks at this resolution (|latitude| > 75° is 3.4 % of the
/// sphere, about 24 elements, one or two cracks per run). The statistics are not singular at
/// the poles: each segment is measured in the tangent frame at its midpoint, whose east axis
/// is undefined only at the pole itself, and an isotropic pattern is isotropic in any frame.
const std::vector<double> BANDS{0, 20, 40, 60, 90};

/// A sphere of radius 8 cm in 700 elements (edges about 1.6 cm), with the fixture's 1 cm layer
/// (E = 1 GPa, threshold 0.1 MPa) and the fixture's toughness, too low to arrest more than a
/// stray extension.
LayerSpec sphere(std::uint64_t seed) {
    LayerSpec s;
    s.kind = mesh::SurfaceKind::Sphere;
    s.size = Vec2(0.08, 0.08);
    s.elements = 700;
    s.seed = seed;
    return s;
}

std::string band_name(std::size_t b) {
    return std::to_string(int(BANDS[b])) + "-" + std::to_string(int(BANDS[b + 1])) + " deg";
}

// === Cylinder (Figs. 5.33-5.34)

/// A trunk of circumference C and height H (m) with about 1 cm elements, growing around its
/// axis: the bark preset's material (E = 1 GPa, threshold 1 MPa, K_IC = 0.1 MPa·√m, 1.5 cm)
/// and growth (0.4 % around, 0.05 % along the axis over the run: four times the threshold
/// strain).
LayerSpec trunk(std::uint64_t seed, double C, double H, double edge = 0.01) {
    LayerSpec s;
    s.kind = mesh::SurfaceKind::Cylinder;
    s.size = Vec2(C, H);
    s.elements = static_cast<std::size_t>(C * H / (std::sqrt(3.0) / 4 * edge * edge));
    s.seed = seed;
    s.young = 1e9;
    s.poisson = 0.3;
    s.threshold = 1e6;
    s.toughness = 1e5;
    s.thickness = 0.015;
    s.growth = {sim::GrowthKind::Anisotropic, 0.004, 0.0005, 0.0};
    return s;
}

/// Lines across the trunk at which fissures are counted.
constexpr int LINES = 16;

/// What a bark run is measured by.
struct Bark {
    double fissures = 0; ///< cracks crossing a horizontal line, mean over LINES heights
    double splits = 0, extensions = 0, arrests = 0;
    double axial = 0, anisotropy = 0, off_axis_deg = 0, rho = 0;
    double fragments = 0, fragment_area = 0;
    double first = 0; ///< time of the first fracture
    /// Σ ℓ|t_y|/H, the mean crossings over all heights, and the mean over 256 lines: checks
    /// of the line count (test::mean_crossings against test::projected_crossings).
    double crofton = 0, fissures_fine = 0;
};

Bark bark_run(const LayerSpec& s, const test::FieldVariations& variations = {}, double duration = 1.0) {
    const auto r = test::run_split_varied(s, variations, false, duration);
    Bark b;
    b.fissures = test::mean_crossings(r.pattern, LINES);
    b.splits = double(r.split.splits);
    b.extensions = double(r.split.extensions);
    b.arrests = double(r.split.arrests);
    b.axial = r.stats.axial_fraction;
    b.anisotropy = r.stats.anisotropy;
    const double d = std::abs(r.stats.dominant_angle_deg - 90.0);
    b.off_axis_deg = std::min(d, 180.0 - d);
    b.rho = r.stats.crack_length_per_area;
    b.fragments = double(r.stats.fragments);
    b.fragment_area = r.stats.mean_fragment_area;
    b.first = r.pattern.events.empty() ? INFINITY : r.pattern.events.front().time;
    b.crofton = test::projected_crossings(r.pattern);
    b.fissures_fine = test::mean_crossings(r.pattern, 256);
    return b;
}

/// Means over seeds of each field.
Bark mean_of(const std::vector<Bark>& runs) {
    Bark m;
    const double n = double(runs.size());
    for (const Bark& b : runs) {
        m.fissures += b.fissures / n;
        m.splits += b.splits / n;
        m.extensions += b.extensions / n;
        m.arrests += b.arrests / n;
        m.axial += b.axial / n;
        m.anisotropy += b.anisotropy / n;
        m.off_axis_deg += b.off_axis_deg / n;
        m.rho += b.rho / n;
        m.fragments += b.fragments / n;
        m.fragment_area += b.fragment_area / n;
        m.first += b.first / n;
    }
    return m;
}

/// Mean over the top nodes of the largest in-surface principal stress (Pa) at time t.
double mean_nodal_stress(const LayerSpec& s, double t) {
    test::Layer layer(s);
    sim::FemModel& m = *layer.model;
    m.set_time(t);
    m.relax();
    double sum = 0;
    for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
        sum += fracture::nodal_stress(m, v).ratio * s.threshold;
    return sum / double(m.mesh().num_vertices());
}

/// Depth of the top Gauss points in the layer (ζ = √(3/5) of [−1, 1]): where fem-split reads
/// the nodal stress (§5.7.1).
const double TOP_GAUSS = 0.5 * (1 + std::sqrt(0.6));

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("claims 5.32: isogonic growth or isotropic shrinkage cracks a sphere isotropically at every latitude") {
        // Isogonic growth to twice the threshold strain (Fig. 5.32 left), three seeds, and
        // isotropic shrinkage of the same size on a static sphere, two seeds. The orientation
        // tensor of the crack segments per latitude band, in the local east-north frame (not
        // the equirectangular texture, which stretches east-west lengths by 1/cos(latitude)).
        std::vector<test::Orientation> pooled(BANDS.size() - 1);
        double worst = 0, worst_shrink = 0, worst_match = 0;
        std::vector<double> growth_length;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            LayerSpec s = sphere(seed);
            s.growth = {sim::GrowthKind::Isogonic, 2e-4, 2e-4, 0.0};
            const auto r = test::run_split_varied(s, {}, false);
            REQUIRE(r.split.splits > 30);
            const auto bands = test::orientation_by_latitude(r.pattern, BANDS);
            test::Orientation all;
            for (std::size_t b = 0; b < bands.size(); ++b) {
                CAPTURE(b);
                REQUIRE(bands[b].count >= 60);
                worst = std::max(worst, bands[b].anisotropy());
                pooled[b].add(bands[b]);
                all.add(bands[b]);
            }
            // The bands together are the whole pattern (pattern_statistics' tensor).
            CHECK(all.length == doctest::Approx(r.stats.crack_length).epsilon(1e-9));
            CHECK(all.anisotropy() == doctest::Approx(r.stats.anisotropy).epsilon(1e-6));
            growth_length.push_back(r.stats.crack_length);
        }
        for (std::uint64_t seed : {1u, 2u}) {
            CAPTURE(seed);
            LayerSpec s = sphere(seed);
            s.shrinkage = {2e-4, 2e-4};
            const auto r = test::run_split_varied(s, {}, false);
            REQUIRE(r.split.splits > 30);
            for (const test::Orientation& o : test::orientation_by_latitude(r.pattern, BANDS))
                worst_shrink = std::max(worst_shrink, o.anisotropy());
            // Growth ≡ shrinkage (digest §7.3): the same strains, so the same cracks.
            worst_match = std::max(worst_match, std::abs(r.stats.crack_length / growth_length[seed - 1] - 1));
        }
        double worst_pooled = 0;
        for (std::size_t b = 0; b < pooled.size(); ++b) {
            CAPTURE(band_name(b));
            test::record_claim("5.32", "isogonic growth: isotropic cracks at every latitude",
                               "anisotropy of crack tangents, |latitude| " + band_name(b) + ", 3 seeds pooled",
                               pooled[b].anisotropy(), "< 0.1");
            CHECK(pooled[b].anisotropy() < 0.1);
            worst_pooled = std::max(worst_pooled, pooled[b].anisotropy());
        }
        test::record_claim("5.32", "isogonic growth: isotropic cracks at every latitude",
                           "largest anisotropy of one band in one run (3 seeds x 4 bands)", worst, "< 0.25");
        test::record_claim("5.32", "isotropic shrinkage: isotropic cracks at every latitude",
                           "largest anisotropy of one band in one run (2 seeds x 4 bands)", worst_shrink, "< 0.25");
        test::record_claim("5.32", "isotropic shrinkage cracks like isogonic growth (digest 7.3)",
                           "largest |crack length shrinkage / growth - 1| (2 seeds)", worst_match, "< 0.03");
        CHECK(worst < 0.25);
        CHECK(worst_shrink < 0.25);
        CHECK(worst_match < 0.03);
    }

    TEST_CASE("claims 5.32: a sphere growing 4x faster along Z cracks along latitude circles at the equator, "
              "isotropically near the poles") {
        // v = (r x, r y, 4 r z) (digest §1.6), r to 1.25 threshold strains. In the tangent plane
        // the growth is r east and r (sin²φ + 4 cos²φ) north: 4:1 at the equator, isotropic at
        // the poles. Cracks run across the faster growth, so east-west near the equator.
        // Seeds 1, 2 and 4: seed 3 stops on a core defect (the skipped test case below).
        std::vector<test::Orientation> pooled(BANDS.size() - 1);
        std::vector<double> equator_east, equator_off;
        for (std::uint64_t seed : {1u, 2u, 4u}) {
            CAPTURE(seed);
            LayerSpec s = sphere(seed);
            s.growth = {sim::GrowthKind::Anisotropic, 1.25e-4, 5e-4, 0.0};
            const auto r = test::run_split_varied(s, {}, false);
            REQUIRE(r.split.splits > 30);
            const auto bands = test::orientation_by_latitude(r.pattern, BANDS);
            for (std::size_t b = 0; b < bands.size(); ++b) {
                REQUIRE(bands[b].count >= 60);
                pooled[b].add(bands[b]);
            }
            equator_east.push_back(bands[0].along_x_fraction());
            equator_off.push_back(bands[0].dominant_off_x_deg());
        }
        const test::Orientation& equator = pooled.front();
        const test::Orientation& poles = pooled.back();
        bool decreasing = true;
        for (std::size_t b = 0; b < pooled.size(); ++b) {
            CAPTURE(band_name(b));
            CAPTURE(pooled[b].anisotropy());
            CAPTURE(pooled[b].dominant_off_x_deg());
            CAPTURE(pooled[b].along_x_fraction());
            if (b > 0) decreasing = decreasing && pooled[b].anisotropy() < pooled[b - 1].anisotropy();
        }
        test::record_claim("5.32", "Z growth 4x: cracks along latitude circles at the equator",
                           "anisotropy of crack tangents, |latitude| < 20 deg, 3 seeds pooled", equator.anisotropy(),
                           "> 0.3");
        test::record_claim("5.32", "Z growth 4x: cracks along latitude circles at the equator",
                           "dominant crack direction from east, |latitude| < 20 deg (deg)",
                           equator.dominant_off_x_deg(), "< 10");
        test::record_claim("5.32", "Z growth 4x: cracks along latitude circles at the equator",
                           "min over seeds of the share of crack length within 30 deg of east, |latitude| < 20 deg",
                           *std::min_element(equator_east.begin(), equator_east.end()), "> 0.5");
        test::record_claim("5.32", "Z growth 4x: isotropic near the poles",
                           "anisotropy of crack tangents, |latitude| > 60 deg, 3 seeds pooled", poles.anisotropy(),
                           "< 0.2");
        test::record_claim("5.32", "Z growth 4x: alignment fades from equator to poles",
                           "pooled anisotropy decreasing over 4 latitude bands", decreasing ? 1.0 : 0.0, "== 1");
        CHECK(equator.anisotropy() > 0.3);
        CHECK(equator.dominant_off_x_deg() < 10.0);
        for (std::size_t i = 0; i < equator_east.size(); ++i) {
            CHECK(equator_east[i] > 0.5);
            CHECK(equator_off[i] < 15.0);
        }
        CHECK(poles.anisotropy() < 0.2);
        CHECK(equator.anisotropy() - poles.anisotropy() > 0.25);
        CHECK(decreasing);
    }

    TEST_CASE("claims 5.32: an edge collapse on the anisotropic sphere leaves no inverted wedge (seed 3)") {
        // Once a defect: fem-split's edge collapse (cut_towards -> FemModel::move_vertex) checked
        // the moved vertex's triangles with the point on the chord, up to a sagitta (about 1 mm
        // here) inside the sphere, and built a folded element (det J < 0) next to a thin one.
        LayerSpec s = sphere(3);
        s.growth = {sim::GrowthKind::Anisotropic, 1.25e-4, 5e-4, 0.0};
        CHECK_NOTHROW(test::run_split(s));
    }

    TEST_CASE("claims 5.33, 5.34: a trunk growing around its axis opens vertical fissures") {
        // The bark preset's material and growth on a 0.5 m trunk (8 cm radius), 6 cm of it, with
        // the preset's threshold texture (±20 %, 8 cm features); three seeds. Control: the same
        // trunk growing along its axis instead cracks in rings.
        sim::VariationOptions uneven;
        uneven.pattern = sim::PatternKind::Noise;
        uneven.amplitude = 0.2;
        uneven.scale = 0.08;
        std::vector<double> axial, anisotropy, off_axis, fissures;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            const Bark b = bark_run(trunk(seed, 0.5, 0.06), {sim::VariationOptions{}, uneven});
            REQUIRE(b.splits >= 5);
            // The fissure count: many lines average to the projected crack length (Crofton),
            // and the 16 lines used below are close to it.
            CHECK(b.fissures_fine == doctest::Approx(b.crofton).epsilon(0.02));
            CHECK(b.fissures == doctest::Approx(b.crofton).epsilon(0.1));
            axial.push_back(b.axial);
            anisotropy.push_back(b.anisotropy);
            off_axis.push_back(b.off_axis_deg);
            fissures.push_back(b.fissures);
        }
        LayerSpec rings = trunk(1, 0.5, 0.06);
        rings.growth.angle_deg = 90; // r1 = 0.4 % along the axis, r2 = 0.05 % around
        const Bark control = bark_run(rings, {sim::VariationOptions{}, uneven});
        CAPTURE(control.axial);
        CAPTURE(control.off_axis_deg);
        CAPTURE(mean(fissures));
        test::record_claim("5.33", "radial growth: vertical fissures",
                           "min over 3 seeds of the axial fraction of crack length",
                           *std::min_element(axial.begin(), axial.end()), "> 0.8");
        test::record_claim("5.33", "radial growth: vertical fissures", "min over 3 seeds of the crack anisotropy",
                           *std::min_element(anisotropy.begin(), anisotropy.end()), "> 0.7");
        test::record_claim("5.33", "radial growth: vertical fissures",
                           "max over 3 seeds of the dominant crack direction's angle from the axis (deg)",
                           *std::max_element(off_axis.begin(), off_axis.end()), "< 10");
        test::record_claim("5.33", "control: growth along the axis cracks in rings",
                           "axial fraction of crack length, growth along the axis", control.axial, "< 0.2");
        for (std::size_t i = 0; i < axial.size(); ++i) {
            CHECK(axial[i] > 0.8);
            CHECK(anisotropy[i] > 0.7);
            CHECK(off_axis[i] < 10.0);
        }
        CHECK(control.axial < 0.2);
        CHECK(control.off_axis_deg > 80.0);
    }

    TEST_CASE("claims 5.33 (Table 5.2 thickness): thicker bark opens fewer, wider-spaced fissures") {
        // Bark 1, 2 and 3 cm thick on a 0.5 m trunk, 5 cm of it, two seeds each. Fissures are
        // counted where they cross 16 horizontal lines; plates are as wide as the circumference
        // over that count. The same sweep on a plane of the same size gives the same counts
        // (on 6 cm of it: 32, 15, 8.5 against 32, 13, 8.3), so this is not the curvature's doing (h/R is 0.13 to
        // 0.38 here; see the curvature tests below).
        const std::vector<double> thickness{0.01, 0.02, 0.03};
        std::vector<Bark> level;
        double min_axial = 1;
        for (double h : thickness) {
            std::vector<Bark> runs;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = trunk(seed, 0.5, 0.05);
                s.thickness = h;
                runs.push_back(bark_run(s));
                REQUIRE(runs.back().splits >= 3);
                min_axial = std::min(min_axial, runs.back().axial);
            }
            level.push_back(mean_of(runs));
        }
        bool fewer = true;
        for (std::size_t i = 0; i < level.size(); ++i) {
            CAPTURE(thickness[i]);
            CAPTURE(level[i].fissures);
            CAPTURE(level[i].splits);
            CAPTURE(level[i].arrests);
            CAPTURE(level[i].fragments);
            CAPTURE(level[i].fragment_area);
            const double width = 0.5 / level[i].fissures;
            test::record_claim("5.33", "thicker bark: fewer fissures",
                               "fissures around the trunk, thickness " + std::to_string(int(thickness[i] * 100 + 0.5))
                                   + " cm (mean over 16 heights, 2 seeds)",
                               level[i].fissures, "decreasing with thickness");
            test::record_claim("5.33", "thicker bark: wider plates",
                               "plate width / thickness, thickness " + std::to_string(int(thickness[i] * 100 + 0.5))
                                   + " cm",
                               width / thickness[i], "in [1, 4]");
            CHECK(width / thickness[i] > 1.0);
            CHECK(width / thickness[i] < 4.0);
            if (i > 0) fewer = fewer && level[i].fissures < 0.8 * level[i - 1].fissures;
        }
        // Plate width ∝ thickness^k from 1 to 3 cm.
        const double k = std::log(level.front().fissures / level.back().fissures) / std::log(3.0);
        test::record_claim("5.33", "plate width tracks the thickness", "k in plate width ~ thickness^k (1 to 3 cm)", k,
                           "in [0.6, 1.6]");
        test::record_claim("5.33", "fragments do not measure plate size",
                           "mean fragment area, 3 cm / 1 cm (fissures are arrested, few plates close)",
                           level.back().fragment_area / level.front().fragment_area, "recorded only");
        CHECK(fewer);
        CHECK(k > 0.6);
        CHECK(k < 1.6);
        CHECK(min_axial > 0.8);
    }

    TEST_CASE("claims 5.33 (Table 5.2 threshold): a higher threshold opens fewer fissures, toughness in proportion") {
        // Thresholds 0.5, 1 and 2 MPa with K_IC/threshold = 0.1 √m as in the preset, two seeds
        // each, 1.5 cm bark. With the toughness in proportion the model is scale free: stresses
        // scale with the strain, Griffith's G with σ² and G_IC with K_IC², so doubling both
        // is the same run with the strain doubled: a higher threshold is an earlier snapshot of
        // one evolution (asserted: 0.5 MPa stopped at t = 0.5 cracks exactly like 1 MPa at
        // t = 1). The final strain is 8, 4 and 2 threshold strains; the count grows with it and
        // saturates between 4 and 8, where the fissures are about 1.8 thicknesses apart.
        const std::vector<double> threshold{0.5e6, 1e6, 2e6};
        std::vector<Bark> level;
        Bark at_one;
        for (double th : threshold) {
            std::vector<Bark> runs;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = trunk(seed, 0.5, 0.05);
                s.threshold = th;
                s.toughness = 0.1 * th;
                runs.push_back(bark_run(s));
                REQUIRE(runs.back().splits >= 3);
            }
            if (th == 1e6) at_one = runs.front();
            level.push_back(mean_of(runs));
        }
        LayerSpec half = trunk(1, 0.5, 0.05);
        half.threshold = 0.5e6;
        half.toughness = 0.05e6;
        const Bark early = bark_run(half, {}, 0.5);
        CHECK(early.splits == at_one.splits);
        CHECK(early.extensions == at_one.extensions);
        CHECK(early.rho == doctest::Approx(at_one.rho).epsilon(1e-3));
        CHECK(early.first == doctest::Approx(at_one.first / 2).epsilon(1e-3));
        bool fewer = true, fewer_starts = true;
        for (std::size_t i = 0; i < level.size(); ++i) {
            CAPTURE(threshold[i]);
            CAPTURE(level[i].fissures);
            CAPTURE(level[i].splits);
            CAPTURE(level[i].extensions);
            CAPTURE(level[i].arrests);
            test::record_claim("5.33", "higher threshold: fewer fissures",
                               "fissures around the trunk, threshold " + std::to_string(threshold[i] / 1e6).substr(0, 3)
                                   + " MPa, K_IC = 0.1 m^0.5 x threshold (2 seeds)",
                               level[i].fissures, "non-increasing with threshold");
            if (i > 0) {
                fewer = fewer && level[i].fissures <= level[i - 1].fissures;
                fewer_starts = fewer_starts && level[i].splits <= level[i - 1].splits;
            }
        }
        test::record_claim("5.33", "higher threshold: fewer fissures", "fissures at 1 MPa / fissures at 2 MPa",
                           level[1].fissures / level[2].fissures, "> 1.2");
        test::record_claim("5.33", "higher threshold: fewer fissures", "fissures at 0.5 MPa / fissures at 2 MPa",
                           level.front().fissures / level.back().fissures, "> 1.25");
        CHECK(fewer);
        CHECK(fewer_starts);
        CHECK(level[1].fissures > 1.2 * level[2].fissures);
        CHECK(level.front().fissures > 1.25 * level.back().fissures);
    }

    TEST_CASE("claims 5.33 (Table 5.2 threshold): at the preset's toughness a low threshold leaves arrested stubs") {
        // The same thresholds at the preset's K_IC = 0.1 MPa·√m. New fissures still get fewer as
        // the threshold rises, but below about 0.8 MPa the fissure count does not follow: a
        // fissure that starts at threshold σ releases about σ²h/E per unit area (3.8 J/m² at
        // 0.5 MPa, 15 J/m² at 1 MPa for h = 1.5 cm), against G_IC = (1 − ν²)K_IC²/E = 9.1 J/m².
        // So at 0.5 MPa almost every extension is arrested and the extra starts stay stubs one or
        // two elements long that few horizontal lines cross: more than twice the new fractures
        // of 1 MPa, but no more fissures. Asserted as it is; the claim holds from 1 to 2 MPa.
        const std::vector<double> threshold{0.5e6, 1e6, 2e6};
        std::vector<Bark> level;
        for (double th : threshold) {
            std::vector<Bark> runs;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = trunk(seed, 0.5, 0.05);
                s.threshold = th;
                runs.push_back(bark_run(s));
                REQUIRE(runs.back().splits >= 3);
            }
            level.push_back(mean_of(runs));
        }
        std::vector<double> accepted;
        for (std::size_t i = 0; i < level.size(); ++i) {
            CAPTURE(threshold[i]);
            CAPTURE(level[i].fissures);
            CAPTURE(level[i].splits);
            accepted.push_back(level[i].extensions / std::max(1.0, level[i].extensions + level[i].arrests));
            CAPTURE(accepted.back());
        }
        test::record_claim("5.33", "higher threshold: fewer fissures (fixed K_IC: not below 0.8 MPa)",
                           "fissures at 0.5 MPa / at 1 MPa, K_IC = 0.1 MPa m^0.5 (2 seeds)",
                           level[0].fissures / level[1].fissures, "< 1.15");
        test::record_claim("5.33", "higher threshold: fewer new fractures (fixed K_IC)",
                           "new fractures at 0.5 MPa / at 1 MPa", level[0].splits / level[1].splits, "> 1.5");
        test::record_claim("5.33", "higher threshold: fewer fissures (fixed K_IC)", "fissures at 1 MPa / at 2 MPa",
                           level[1].fissures / level[2].fissures, "> 1.2");
        test::record_claim("5.33", "Griffith arrests the fissures of a low threshold",
                           "share of tip extensions accepted at 0.5 MPa", accepted[0], "< 0.2");
        test::record_claim("5.33", "Griffith lets the fissures of a high threshold run",
                           "min share of tip extensions accepted at 1 and 2 MPa", std::min(accepted[1], accepted[2]),
                           "> 0.5");
        CHECK(level[0].splits > 1.5 * level[1].splits);
        CHECK(level[1].splits > level[2].splits);
        CHECK(level[0].fissures < 1.15 * level[1].fissures);
        CHECK(level[1].fissures > 1.2 * level[2].fissures);
        CHECK(accepted[0] < 0.2);
        CHECK(accepted[1] > 0.5);
        CHECK(accepted[2] > 0.5);
    }

    TEST_CASE("claims curvature: a trunk's stress approaches the plane's as its radius grows, as a thick ring's") {
        // The surfaces cannot vary the radius alone: a cylinder's radius is its circumference
        // over 2π. So trunks of circumference 0.3, 0.6 and 1.2 m (R = 4.8, 9.5, 19 cm) are
        // compared with planes of the same size and elements (1.1 cm edges), the 1.5 cm bark
        // grown to t = 1 without fracture. On the plane the top stress is the thin layer's
        // E/(1 − ν²)(ε_θ + ν ε_z); on a trunk the bark's outside is stretched less (its radius
        // is R + h), by the factor a thick ring (Lamé) predicts, which tends to 1 as h/R → 0.
        const double eps_u = 0.004, eps_v = 0.0005, E = 1e9, nu = 0.3, h = 0.015;
        const double thin = E / (1 - nu * nu) * (eps_u + nu * eps_v);
        std::vector<double> excess; // plane stress / trunk stress − 1
        for (double C : {0.3, 0.6, 1.2}) {
            CAPTURE(C);
            LayerSpec cyl = trunk(1, C, 0.05, 0.011);
            LayerSpec plane = cyl;
            plane.kind = mesh::SurfaceKind::Plane;
            // Unloaded, the bark on a curved trunk is stress free (reference shapes from vertex
            // normals, digest §1.10 [I]).
            CHECK(mean_nodal_stress(cyl, 0.0) < 1e-6 * thin);
            const double on_plane = mean_nodal_stress(plane, 1.0), on_trunk = mean_nodal_stress(cyl, 1.0);
            CHECK(on_plane == doctest::Approx(thin).epsilon(0.01));
            const double R = C / TWO_PI;
            const double lame = test::lame_hoop_stress(E, nu, R, h, TOP_GAUSS, eps_u, eps_v);
            const double measured = on_plane / on_trunk - 1, predicted = thin / lame - 1;
            CAPTURE(h / R);
            CAPTURE(measured);
            CAPTURE(predicted);
            test::record_claim("curvature", "bark stress on a trunk approaches the plane's as R grows",
                               "(plane / trunk stress - 1) / Lame's, h/R = " + std::to_string(h / R).substr(0, 5),
                               measured / predicted, "in [0.8, 1.5]");
            CHECK(measured / predicted > 0.8);
            CHECK(measured / predicted < 1.5);
            excess.push_back(measured);
        }
        // O(h/R): doubling the radius halves the difference.
        for (std::size_t i = 1; i < excess.size(); ++i) {
            const double rate = excess[i - 1] / excess[i];
            test::record_claim("curvature", "bark stress on a trunk approaches the plane's as R grows",
                               "stress excess at R / at 2R (O(1/R): 2)", rate, "in [1.7, 2.5]");
            CHECK(rate > 1.7);
            CHECK(rate < 2.5);
        }
        CHECK(excess.back() < 0.2);
    }

    TEST_CASE("claims curvature: a trunk's fissures and events match the plane's from 4 layer thicknesses of radius, "
              "its first fracture is later by Lame's factor") {
        // Trunks and planes of circumference 0.3, 0.6, 1.2 m (5 cm tall) cracked with the
        // bark material, two seeds each. What is compared: the time of the first fracture, the
        // fissures per metre of circumference, new fractures per area and crack length per area.
        const std::vector<double> circumference{0.3, 0.6, 1.2};
        std::vector<double> first_ratio, fissure_ratio, split_ratio, rho_ratio, arrest_ratio;
        for (double C : circumference) {
            std::vector<Bark> cyl, plane;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = trunk(seed, C, 0.05, 0.011);
                cyl.push_back(bark_run(s));
                s.kind = mesh::SurfaceKind::Plane;
                plane.push_back(bark_run(s));
            }
            const Bark c = mean_of(cyl), p = mean_of(plane);
            CAPTURE(C);
            CAPTURE(c.fissures);
            CAPTURE(p.fissures);
            CAPTURE(c.arrests);
            CAPTURE(p.arrests);
            first_ratio.push_back(c.first / p.first);
            fissure_ratio.push_back(c.fissures / p.fissures);
            split_ratio.push_back(c.splits / p.splits);
            rho_ratio.push_back(c.rho / p.rho);
            arrest_ratio.push_back(c.arrests / std::max(1.0, p.arrests));
            const double R = C / TWO_PI;
            const double lame = test::lame_hoop_stress(1e9, 0.3, R, 0.015, TOP_GAUSS, 0.004, 0.0005);
            const double thin = 1e9 / (1 - 0.09) * (0.004 + 0.3 * 0.0005);
            // Asserted below: within 15 % at every radius (R = 4.3 to 17 layer thicknesses). Until
            // 2026-12-07 the trunk had 0.68× the plane's fissures at C = 0.3 m, 0.87× at 1.2 m: tips
            // stopped at the seams (test_seams.cpp), which the plane has two of across its fissures'
            // paths and the trunk one; with them crossed, no dependence on the radius is left
            // that two seeds can resolve (0.93-1.04).
            const std::string converge = "|1 - x| < 0.15";
            const std::string at = ", C = " + std::to_string(C).substr(0, 3) + " m (cylinder / plane, 2 seeds)";
            test::record_claim("curvature", "first fracture later on a trunk by Lame's factor",
                               "(first fracture time ratio - 1) / (Lame stress ratio - 1)" + at,
                               (first_ratio.back() - 1) / (thin / lame - 1), "in [0.8, 1.5]");
            test::record_claim("curvature", "fissures match the plane's", "fissure count ratio" + at,
                               fissure_ratio.back(), converge);
            test::record_claim("curvature", "new fractures match the plane's", "new fracture count ratio" + at,
                               split_ratio.back(), converge);
            test::record_claim("curvature", "crack density matches the plane's", "rho_c ratio" + at, rho_ratio.back(),
                               converge);
            test::record_claim("curvature", "arrests approach the plane's (slowly)", "arrest count ratio" + at,
                               arrest_ratio.back(), "recorded");
            CHECK((first_ratio.back() - 1) / (thin / lame - 1) > 0.8);
            CHECK((first_ratio.back() - 1) / (thin / lame - 1) < 1.5);
        }
        for (const std::vector<double>* r : {&fissure_ratio, &split_ratio, &rho_ratio})
            for (double x : *r)
                CHECK(std::abs(x - 1) < 0.15);
    }
}
