// Thesis claims about whole crack patterns on the plane: crack density follows the layer
// thickness (Fig. 5.29, here with fem-split) and perturbed material makes cracks less straight
// (Fig. 5.31).

#include "support/accuracy.hpp"
#include "support/claims_fixture.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <map>
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

/// Smooth noise of ±80 % with features of 2 cm (about two elements), the texture of Fig. 5.31.
sim::VariationOptions texture() {
    sim::VariationOptions noise;
    noise.pattern = sim::PatternKind::Noise;
    noise.amplitude = 0.8;
    noise.scale = 0.02;
    return noise;
}

/// Horizontal-only growth (Fig. 5.27 bottom, the unperturbed run of Fig. 5.31) on a square
/// tile of side `size` (m).
LayerSpec horizontal_growth(std::uint64_t seed, std::size_t elements, double size) {
    LayerSpec s;
    s.size = Vec2(size, size);
    s.elements = elements;
    s.seed = seed;
    s.growth = {sim::GrowthKind::Anisotropic, 3e-4, 0.0, 0.0};
    return s;
}

/// Straightness of a run's cracks: tortuosity of chains at least 3 mean edges long, and the
/// orientation spread.
struct Straightness {
    std::vector<double> tortuosity, spread, anisotropy;
    void add(const test::FractureRun& r) {
        const double h = mesh::mesh_quality(r.pattern.mesh).edge_mean;
        const fracture::CrackPathStatistics cp = fracture::crack_path_statistics(r.pattern, 3 * h);
        REQUIRE(cp.chains > 3);
        tortuosity.push_back(cp.tortuosity);
        spread.push_back(cp.orientation_spread_deg);
        anisotropy.push_back(r.stats.anisotropy);
    }
};

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("claims 5.29 (fem-split): a layer thickening across the tile cracks more densely where it is thin") {
        // Thickness 0.5 cm at v = 0 rising linearly to 2 cm at v = 1 (4×, as the thesis' 1 → 4 cm),
        // drying (isotropic shrinkage to three times the threshold strain). The periodic tile
        // jumps from thick back to thin at v = 1 → 0, so bands next to it are left out.
        std::vector<double> density_ratio, size_exponent, area_ratio;
        bool monotone = true;
        for (std::uint64_t seed : {1u, 2u}) {
            CAPTURE(seed);
            LayerSpec s;
            s.size = Vec2(0.2, 0.2);
            s.elements = 600;
            s.seed = seed;
            s.thickness = 0.005;
            s.thickness_end = 0.02;
            s.shrinkage = {3e-4, 3e-4};
            const auto r = test::run_split(s);
            REQUIRE(r.split.splits > 20);
            // ρ_c in four bands of v from 0.05 to 0.95 (thin to thick).
            constexpr int BANDS = 4;
            std::vector<double> band(BANDS, 0.0);
            const double band_area = 0.9 / BANDS * r.stats.total_area;
            for (const auto& seg : fracture::crack_segments(r.pattern)) {
                const double v = seg.uv.y();
                if (v <= 0.05 || v >= 0.95) continue;
                const auto b = std::min<std::size_t>(BANDS - 1, static_cast<std::size_t>((v - 0.05) / 0.9 * BANDS));
                band[b] += seg.weight * seg.length() / band_area;
            }
            for (std::size_t b = 1; b < band.size(); ++b)
                monotone = monotone && band[b] < band[b - 1];
            density_ratio.push_back((band[0] + band[1]) / (band[2] + band[3]));
            CAPTURE(band[0]);
            CAPTURE(band[3]);
            // Fragments: area and area-weighted mean thickness; thin (< 1 cm) against thick (> 1.5 cm).
            const auto& p = r.pattern;
            std::map<int, std::pair<double, double>> fragment; // area, Σ area · thickness
            for (std::size_t f = 0; f < p.mesh.num_faces(); ++f) {
                if (p.fragment[f] < 0) continue;
                double th = 0;
                for (mesh::VertexId w : p.mesh.faces[mesh::face_id(f)].v)
                    th += p.thickness[mesh::ix(w)] / 3.0;
                const double a = p.mesh.face_area(mesh::face_id(f));
                fragment[p.fragment[f]].first += a;
                fragment[p.fragment[f]].second += a * th;
            }
            std::vector<double> thin_area, thin_th, thick_area, thick_th;
            for (const auto& [id, at] : fragment) {
                const double th = at.second / at.first;
                if (th < 0.01) {
                    thin_area.push_back(at.first);
                    thin_th.push_back(th);
                }
                if (th > 0.015) {
                    thick_area.push_back(at.first);
                    thick_th.push_back(th);
                }
            }
            REQUIRE(thin_area.size() >= 5);
            REQUIRE(thick_area.size() >= 5);
            area_ratio.push_back(mean(thick_area) / mean(thin_area));
            // Fragment size (√area) ∝ thickness^k between the two groups.
            size_exponent.push_back(std::log(std::sqrt(area_ratio.back())) / std::log(mean(thick_th) / mean(thin_th)));
        }
        test::record_claim("5.29", "more cracks where the layer is thin (fem-split)",
                           "min over seeds of rho_c(thin half) / rho_c(thick half)",
                           std::min(density_ratio[0], density_ratio[1]), "> 1.4");
        test::record_claim("5.29", "rho_c decreases with thickness (fem-split)",
                           "rho_c over 4 bands of thickness decreasing, all seeds", monotone ? 1.0 : 0.0, "== 1");
        test::record_claim("5.29", "local fragment size grows with thickness (fem-split)",
                           "min over seeds of mean fragment area, thick (> 1.5 cm) / thin (< 1 cm)",
                           std::min(area_ratio[0], area_ratio[1]), "> 2");
        test::record_claim("5.29", "fragment size roughly proportional to thickness (fem-split)",
                           "mean over seeds of k in sqrt(area) ~ thickness^k", mean(size_exponent), "in [0.5, 1.5]");
        CHECK(std::min(density_ratio[0], density_ratio[1]) > 1.4);
        CHECK(monotone);
        CHECK(std::min(area_ratio[0], area_ratio[1]) > 2.0);
        CHECK(mean(size_exponent) > 0.5);
        CHECK(mean(size_exponent) < 1.5);
    }

    TEST_CASE("claims 5.31 (fem-remove): a perturbed E and threshold, or thickness, make the cracks of horizontal "
              "growth less straight") {
        // Element removal, horizontal-only growth: straight-ish cracks across the stretch. The same
        // with E and threshold perturbed by one texture (Fig. 5.31 top) and with the thickness
        // perturbed (bottom). Both make the cracks wander: longer paths between junctions and
        // a wider spread of directions, and a weaker overall alignment.
        Straightness plain, material, height;
        for (std::uint64_t seed : {1u, 2u}) {
            CAPTURE(seed);
            const LayerSpec s = horizontal_growth(seed, 600, 0.2);
            plain.add(test::run_removal_varied(s, {}));
            LayerSpec perturbed = s;
            perturbed.young_variation = texture();
            material.add(test::run_removal_varied(perturbed, {sim::VariationOptions{}, texture()}));
            height.add(test::run_removal_varied(s, {texture(), sim::VariationOptions{}}));
        }
        const double d_tort_material = mean(material.tortuosity) - mean(plain.tortuosity);
        const double d_tort_height = mean(height.tortuosity) - mean(plain.tortuosity);
        const double d_spread_material = mean(material.spread) - mean(plain.spread);
        const double d_spread_height = mean(height.spread) - mean(plain.spread);
        CAPTURE(mean(plain.tortuosity));
        CAPTURE(mean(plain.spread));
        test::record_claim("5.31", "perturbed E and threshold: cracks less straight (fem-remove)",
                           "mean tortuosity, perturbed - unperturbed (2 seeds)", d_tort_material, "> 0.02");
        test::record_claim("5.31", "perturbed E and threshold: cracks less straight (fem-remove)",
                           "mean orientation spread, perturbed - unperturbed (deg)", d_spread_material, "> 3");
        test::record_claim("5.31", "perturbed thickness: similar twisting (fem-remove)",
                           "mean tortuosity, perturbed - unperturbed (2 seeds)", d_tort_height, "> 0.02");
        test::record_claim("5.31", "perturbed thickness: similar twisting (fem-remove)",
                           "mean orientation spread, perturbed - unperturbed (deg)", d_spread_height, "> 3");
        CHECK(d_tort_material > 0.02);
        CHECK(d_spread_material > 3.0);
        CHECK(d_tort_height > 0.02);
        CHECK(d_spread_height > 3.0);
        CHECK(mean(material.anisotropy) < mean(plain.anisotropy));
        CHECK(mean(height.anisotropy) < mean(plain.anisotropy));
    }

    TEST_CASE("claims 5.31 (fem-split): perturbed material does not make split cracks less straight") {
        // The same three runs with element splitting (on a 0.15 m tile with the same element
        // size, to save time). The claim does not hold here: a bonded layer takes its strain
        // from the background, so a stiffness texture scales the stress but does not turn its
        // principal direction, and cracks cut along that direction (Figs. 5.22-5.23); a
        // threshold texture only moves where cracks start (tips extend by Griffith's test,
        // which does not use the threshold). The thickness texture does not twist them either
        // (on a 0.2 m tile with 600 elements: +0.005 tortuosity, +0.9°). What holds is
        // asserted: all runs stay straight and aligned, within small margins of the
        // unperturbed run; fem-remove (the test above) does twist.
        Straightness plain, material, height;
        for (std::uint64_t seed : {1u, 2u}) {
            CAPTURE(seed);
            const LayerSpec s = horizontal_growth(seed, 340, 0.15);
            plain.add(test::run_split_varied(s, {}, false));
            LayerSpec perturbed = s;
            perturbed.young_variation = texture();
            material.add(test::run_split_varied(perturbed, {sim::VariationOptions{}, texture()}, false));
            height.add(test::run_split_varied(s, {texture(), sim::VariationOptions{}}, false));
        }
        const double d_tort_material = mean(material.tortuosity) - mean(plain.tortuosity);
        const double d_tort_height = mean(height.tortuosity) - mean(plain.tortuosity);
        const double d_spread_material = mean(material.spread) - mean(plain.spread);
        const double d_spread_height = mean(height.spread) - mean(plain.spread);
        CAPTURE(mean(plain.tortuosity));
        CAPTURE(mean(plain.spread));
        test::record_claim("5.31", "perturbed E and threshold: cracks less straight (fem-split: does not hold)",
                           "mean tortuosity, perturbed - unperturbed (2 seeds)", d_tort_material, "|.| < 0.02");
        test::record_claim("5.31", "perturbed E and threshold: cracks less straight (fem-split: does not hold)",
                           "mean orientation spread, perturbed - unperturbed (deg)", d_spread_material, "|.| < 4");
        test::record_claim("5.31", "perturbed thickness: similar twisting (fem-split: barely)",
                           "mean tortuosity, perturbed - unperturbed (2 seeds)", d_tort_height, "|.| < 0.02");
        test::record_claim("5.31", "perturbed thickness: similar twisting (fem-split: barely)",
                           "mean orientation spread, perturbed - unperturbed (deg)", d_spread_height, "|.| < 4");
        for (const Straightness* run : {&plain, &material, &height})
            for (std::size_t i = 0; i < run->tortuosity.size(); ++i) {
                CHECK(run->tortuosity[i] < 1.05);
                CHECK(run->anisotropy[i] > 0.85);
            }
        CHECK(std::abs(d_tort_material) < 0.02);
        CHECK(std::abs(d_spread_material) < 4.0);
        CHECK(std::abs(d_tort_height) < 0.02);
        CHECK(std::abs(d_spread_height) < 4.0);
    }
}
