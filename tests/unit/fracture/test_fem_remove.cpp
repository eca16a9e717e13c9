#include "fracture/fem_remove/fem_remove.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <numeric>

using namespace crackle;
using test::LayerSpec;

namespace {

/// A 0.2 m periodic mud-like plane, 1 cm thick, loaded to about four times its threshold strain.
LayerSpec base_spec(std::uint64_t seed) {
    LayerSpec s;
    s.size = Vec2(0.2, 0.2);
    s.elements = 800;
    s.seed = seed;
    return s;
}

double mean(const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("fem-remove: isogonic growth gives an isotropic crack network") {
        std::vector<double> a, psi6;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            LayerSpec s = base_spec(seed);
            s.growth = {sim::GrowthKind::Isogonic, 3e-4, 3e-4, 0};
            const auto r = test::run_removal(s);
            CAPTURE(seed);
            CHECK(r.stats.fragments > 20);
            CHECK(r.stats.anisotropy < 0.15);
            CHECK(r.stats.psi6 < 0.3); // no lattice alignment on a semi-random mesh
            a.push_back(r.stats.anisotropy);
            psi6.push_back(r.stats.psi6);
        }
        CHECK(mean(a) < 0.08);
        test::record_claim("5.27", "isogonic growth gives an isotropic network (fem-remove)",
                           "anisotropy a, mean of 3 seeds", mean(a), "< 0.08 (each seed < 0.15)");
        test::record_claim("5.27", "isogonic growth: no alignment with the mesh (fem-remove)",
                           "lattice alignment psi6, largest of 3 seeds", *std::max_element(psi6.begin(), psi6.end()),
                           "< 0.3");
    }

    TEST_CASE("fem-remove: growth along one axis gives cracks perpendicular to it (Fig. 5.27)") {
        for (double angle : {0.0, 90.0}) {
            std::vector<double> a, along;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = base_spec(seed);
                s.growth = {sim::GrowthKind::Anisotropic, 4e-4, 0.0, angle};
                const auto r = test::run_removal(s);
                a.push_back(r.stats.anisotropy);
                // Angle between the dominant crack tangent and the growth direction, in [0, 90].
                double d = std::abs(r.stats.dominant_angle_deg - angle);
                d = std::min(d, 180.0 - d);
                along.push_back(d);
            }
            CAPTURE(angle);
            CHECK(mean(a) > 0.45);
            for (double d : along)
                CHECK(d > 75.0);
            const std::string growth = angle == 0.0 ? "growth along u" : "growth along v";
            test::record_claim("5.27", "one-axis growth: an anisotropic network (fem-remove, " + growth + ")",
                               "anisotropy a, mean of 2 seeds", mean(a), "> 0.45");
            test::record_claim("5.27", "one-axis growth: cracks perpendicular to it (fem-remove, " + growth + ")",
                               "angle between dominant crack direction and growth, smallest of 2 seeds [deg]",
                               *std::min_element(along.begin(), along.end()), "> 75");
        }
    }

    TEST_CASE("fem-remove: drying mud meets mostly at T-junctions (Fig. 5.28)") {
        std::vector<double> t, y;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            LayerSpec s = base_spec(seed);
            s.shrinkage = {3e-4, 3e-4};
            const auto r = test::run_removal(s);
            CHECK(r.stats.junctions > 30);
            t.push_back(r.stats.t_junction_fraction);
            y.push_back(r.stats.y_junction_fraction);
        }
        CHECK(mean(t) > 1.5 * mean(y));
        test::record_claim("5.28", "T-junctions outnumber Y-junctions (fem-remove)",
                           "T-junction fraction / Y-junction fraction, means of 3 seeds", mean(t) / mean(y), "> 1.5");
    }

    TEST_CASE("fem-remove: a region of lowered threshold collects the cracks (Fig. 5.26)") {
        // Threshold 0.2·p0 on the left half of the tile, 1.8·p0 on the right (the "breaking
        // heart": lowered inside, high enough outside that crack-tip stresses do not carry over).
        auto img = std::make_shared<GrayImage>();
        img->width = 8;
        img->height = 8;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                img->pixels.push_back(x < 4 ? 0.0f : 1.0f);
        sim::VariationOptions v;
        v.pattern = sim::PatternKind::Image;
        v.amplitude = 0.8;
        v.image = img;
        LayerSpec s = base_spec(5);
        // Enough to crack the soft half (ratio ≈ 3.2 at the end) but not the hard half (≈ 0.36).
        s.growth = {sim::GrowthKind::Isogonic, 0.45e-4, 0.45e-4, 0};
        const auto r = test::run_removal(s, 1.0, 0.0, &v);
        double left = 0, total = 0;
        for (const auto& seg : fracture::crack_segments(r.pattern)) {
            const double len = seg.weight * seg.length();
            total += len;
            // Away from the soft/hard borders at u = 0, 0.5.
            if (seg.uv.x() > 0.05 && seg.uv.x() < 0.45) left += len;
        }
        REQUIRE(total > 0);
        CHECK(left / total > 0.75); // the band is 40 % of the tile
        test::record_claim("5.26", "cracks form only where the threshold is lowered (fem-remove)",
                           "share of crack length inside the lowered band (40 % of the tile)", left / total, "> 0.75");
    }

    TEST_CASE("fem-remove: thicker layers crack less (Fig. 5.29)") {
        std::vector<double> thin, thick;
        for (std::uint64_t seed : {1u, 2u}) {
            LayerSpec s = base_spec(seed);
            s.size = Vec2(0.3, 0.3);
            s.elements = 1500;
            s.shrinkage = {3e-4, 3e-4};
            s.thickness = 0.01;
            thin.push_back(test::run_removal(s).stats.crack_length_per_area);
            s.thickness = 0.03;
            thick.push_back(test::run_removal(s).stats.crack_length_per_area);
        }
        CHECK(mean(thin) > 1.4 * mean(thick));
        test::record_claim("5.29", "more cracks where the layer is thin (fem-remove, 1 cm vs 3 cm)",
                           "rho_c(1 cm) / rho_c(3 cm), means of 2 seeds", mean(thin) / mean(thick), "> 1.4");
    }

    TEST_CASE("fem-remove: growth by s and shrinkage by 1/s remove the same elements in the same order (digest 7.3)") {
        // A noisy threshold decides where cracks start; a uniform layer would tie everywhere and
        // leave the choice to round-off.
        sim::VariationOptions noise;
        noise.pattern = sim::PatternKind::Noise;
        noise.amplitude = 0.2;
        noise.scale = 0.05;
        // Cracking strains of several per cent: σ_th(1 − ν)/E = 0.035 on average, events from 3 %
        // (the first crack sets off 40 removals at once) up to r·t = 15 %. There the exact map
        // r·t = s/(1 − s) and the linearised r·t = s differ by 3 % to 15 %, 30 to 150 times the
        // tolerance.
        LayerSpec s = base_spec(4);
        s.elements = 500;
        s.threshold = 5e7;
        const double r = 0.15, t = 1.0, scale = 1 + r * t;
        LayerSpec grow = s, shrink = s;
        grow.growth = {sim::GrowthKind::Isogonic, r, r, 0};
        const double rate = (1 - 1 / scale) / t;
        shrink.shrinkage = {rate, rate};
        // K(t) = (1 − s)·K₀ leaves the displacements unchanged, but σ = D·B·q uses the B of the
        // shape K was built on: never rebuilt (refresh 1), every event falls at r·t = s; at the
        // default 1e-2, 1 % off the exact map. Rebuilt every 1e-4 of shrinkage, 1e-4 off.
        shrink.fem.stiffness_refresh = 1e-4;
        const auto a = test::run_removal(grow, t, 0.0, &noise);
        const auto b = test::run_removal(shrink, t, 0.0, &noise);
        REQUIRE(a.pattern.events.size() > 200);
        REQUIRE(b.pattern.events.size() == a.pattern.events.size());
        const std::size_t n = a.pattern.events.size();
        std::size_t same = 0, times = 0;
        double worst = 0, nearest_linearised = std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < n; ++i) {
            same += (a.pattern.events[i].position - b.pattern.events[i].position).norm() < 1e-12;
            times += i == 0 || a.pattern.events[i].time != a.pattern.events[i - 1].time;
            // Same strain history: ε = r·t against s/(1 − s); the event times map accordingly.
            const double s_b = rate * b.pattern.events[i].time, eps_a = r * a.pattern.events[i].time;
            worst = std::max(worst, std::abs(eps_a - s_b / (1 - s_b)) / (s_b / (1 - s_b)));
            nearest_linearised = std::min(nearest_linearised, std::abs(eps_a - s_b) / s_b);
        }
        CAPTURE(n);
        CAPTURE(times);
        CHECK(times > 50);   // the map is checked at many strains, not at one cascade
        CHECK(worst < 1e-3); // relative: the refresh tolerance, the time search's and CG's
        CHECK(nearest_linearised > 20 * 1e-3);
        CHECK(same == n);
        test::record_claim("7.3 growth≡shrinkage", "the same elements removed in the same order (fem-remove)",
                           "share of all events at the same element", double(same) / double(n), "= 1");
        test::record_claim("7.3 growth≡shrinkage", "event strains map r·t = s/(1 − s) (fem-remove)",
                           "largest relative strain mismatch over all events, strains 3-15 %", worst, "< 1e-3");
        test::record_claim("7.3 growth≡shrinkage", "event strains do not map r·t = s (fem-remove)",
                           "smallest relative mismatch of r·t = s over the same events", nearest_linearised,
                           "> 2e-2 (20 × the tolerance)");
    }

    TEST_CASE("fem-remove: events are in time order and a seed reproduces the run exactly") {
        LayerSpec s = base_spec(9);
        s.elements = 400;
        s.shrinkage = {3e-4, 1e-4};
        const auto a = test::run_removal(s);
        const auto b = test::run_removal(s);
        REQUIRE(a.pattern.events.size() == b.pattern.events.size());
        for (std::size_t i = 0; i < a.pattern.events.size(); ++i) {
            CHECK(a.pattern.events[i].position == b.pattern.events[i].position);
            if (i > 0) CHECK(a.pattern.events[i].time >= a.pattern.events[i - 1].time);
            CHECK(a.pattern.events[i].ratio > 1.0);
        }
        CHECK(a.pattern.final_time == doctest::Approx(1.0));
    }

    TEST_CASE(
        "fem-remove: dynamic subdivision refines only where cracks run and matches a uniform fine mesh (Fig. 5.16)") {
        // A 3 cm layer cracks sparsely: start from 100 coarse elements and refine candidates
        // longer than 1.4 cm, against a uniform mesh of 1500 elements (longest edges ≈ 1.7 cm).
        std::vector<double> adaptive_rho, uniform_rho, adaptive_elems, uniform_elems;
        for (std::uint64_t seed : {1u, 2u}) {
            LayerSpec coarse = base_spec(seed);
            coarse.elements = 100;
            coarse.thickness = 0.03;
            coarse.shrinkage = {3e-4, 3e-4};
            const auto a = test::run_removal(coarse, 1.0, 0.014);
            LayerSpec fine = coarse;
            fine.elements = 1500;
            const auto u = test::run_removal(fine);
            CHECK(a.removal.subdivisions > 50);
            CHECK(a.pattern.mesh.validate() == "");
            adaptive_rho.push_back(a.stats.crack_length_per_area);
            uniform_rho.push_back(u.stats.crack_length_per_area);
            adaptive_elems.push_back(double(a.pattern.mesh.num_faces()));
            uniform_elems.push_back(double(u.pattern.mesh.num_faces()));
        }
        CHECK(mean(adaptive_rho) == doctest::Approx(mean(uniform_rho)).epsilon(0.25));
        CHECK(mean(adaptive_elems) < 0.75 * mean(uniform_elems));
        test::record_claim("5.16", "adaptive subdivision gives a result comparable to a uniform fine mesh (fem-remove)",
                           "rho_c adaptive / rho_c uniform (1500), means of 2 seeds",
                           mean(adaptive_rho) / mean(uniform_rho), "|Δρ_c| < 0.25·(1 + max ρ_c): about 25 %");
        test::record_claim("5.16", "adaptive subdivision needs fewer elements (fem-remove; wall time not measured)",
                           "elements adaptive / uniform, means of 2 seeds", mean(adaptive_elems) / mean(uniform_elems),
                           "< 0.75");
    }
}
