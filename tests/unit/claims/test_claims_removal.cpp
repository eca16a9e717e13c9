// Thesis claims of Figs. 5.10-5.11 about fracture by element removal: coarse meshes give wide
// cracks (a crack is at least one removed element wide), and the pattern should settle as the
// mesh is refined.

#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace crackle;
using test::LayerSpec;

TEST_SUITE("claims") {
    TEST_CASE("claims 5.10, 5.11: removed cracks are about one element wide, crack density keeps rising with "
              "refinement") {
        // A drying mud layer (1 cm, shrinkage to twice the threshold strain) on a 0.15 m tile at
        // 225, 450 and 900 elements (mean edges 1.6, 1.1 and 0.8 cm), three seeds each.
        //
        // Crack width = removed area / crack length (the length counts each lip ½, so a band of
        // removed elements has its centre-line length). It is proportional to the element size:
        // asserted. The claim that N_f and ρ_c approach a limit does not hold over this range:
        // both keep rising, ρ_c by 15-25 % per level (about ∝ h^-½). The successive differences
        // shrink a little here but not on a 0.2 m tile, and a one-seed run there at 400 … 6400
        // elements went on rising: 37, 47, 57, 65, 76 1/m (edges 1.6 … 0.4 cm). Element removal compares the
        // element stress with the threshold, and the stress a tip element sees grows as the
        // element shrinks (σ ∝ 1/√r at a crack tip), so finer meshes crack more. The test
        // asserts that documented trend (so a change of it shows up), not convergence.
        const std::vector<std::size_t> levels{225, 450, 900};
        std::vector<double> h(levels.size(), 0.0), width(levels.size(), 0.0), rho(levels.size(), 0.0),
            fragments(levels.size(), 0.0);
        const std::vector<std::uint64_t> seeds{1, 2, 3};
        for (std::size_t i = 0; i < levels.size(); ++i)
            for (std::uint64_t seed : seeds) {
                LayerSpec s;
                s.size = Vec2(0.15, 0.15);
                s.elements = levels[i];
                s.seed = seed;
                s.shrinkage = {2e-4, 2e-4};
                const auto r = test::run_removal(s);
                double removed = 0;
                for (std::size_t f = 0; f < r.pattern.mesh.num_faces(); ++f)
                    if (r.pattern.removed[f]) removed += r.pattern.mesh.face_area(mesh::face_id(f));
                REQUIRE(r.stats.crack_length > 0);
                const double n = double(seeds.size());
                h[i] += mesh::mesh_quality(r.pattern.mesh).edge_mean / n;
                width[i] += removed / r.stats.crack_length / n;
                rho[i] += r.stats.crack_length_per_area / n;
                fragments[i] += double(r.stats.fragments) / n;
            }
        double min_ratio = INFINITY, max_ratio = 0;
        for (std::size_t i = 0; i < levels.size(); ++i) {
            CAPTURE(levels[i]);
            CAPTURE(width[i] / h[i]);
            CAPTURE(rho[i]);
            CAPTURE(fragments[i]);
            min_ratio = std::min(min_ratio, width[i] / h[i]);
            max_ratio = std::max(max_ratio, width[i] / h[i]);
        }
        // Power laws over the two refinements: width ∝ h^a, ρ_c ∝ h^-b.
        const double log_h = std::log(h.front() / h.back());
        const double width_exponent = std::log(width.front() / width.back()) / log_h;
        const double rho_exponent = std::log(rho.back() / rho.front()) / log_h;
        const double rise1 = rho[1] / rho[0], rise2 = rho[2] / rho[1];
        const double settling = (rho[2] - rho[1]) / (rho[1] - rho[0]); // < 1: differences shrink
        test::record_claim("5.10", "crack width proportional to element size", "min over levels of width / mean edge",
                           min_ratio, ">= 0.7");
        test::record_claim("5.10", "crack width proportional to element size", "max over levels of width / mean edge",
                           max_ratio, "<= 1.5");
        test::record_claim("5.10", "crack width proportional to element size", "exponent a of width ~ h^a",
                           width_exponent, "in [0.8, 1.5]");
        test::record_claim("5.11", "N_f and rho_c approach a limit (does not hold)", "rho_c(450) / rho_c(225)", rise1,
                           "in [1.05, 1.4]");
        test::record_claim("5.11", "N_f and rho_c approach a limit (does not hold)", "rho_c(900) / rho_c(450)", rise2,
                           "in [1.05, 1.4]");
        test::record_claim("5.11", "N_f and rho_c approach a limit (does not hold)",
                           "(rho_c(900) - rho_c(450)) / (rho_c(450) - rho_c(225)) (< 1: differences shrink)", settling,
                           "not asserted");
        test::record_claim("5.11", "N_f and rho_c approach a limit (does not hold)", "exponent b of rho_c ~ h^-b",
                           rho_exponent, "in [0.2, 0.8]");
        test::record_claim("5.11", "N_f and rho_c approach a limit (does not hold)", "N_f(900) / N_f(225)",
                           fragments[2] / fragments[0], "> 1");
        CHECK(min_ratio >= 0.7);
        CHECK(max_ratio <= 1.5);
        CHECK(width_exponent >= 0.8);
        CHECK(width_exponent <= 1.5);
        CHECK(rise1 > 1.05);
        CHECK(rise1 < 1.4);
        CHECK(rise2 > 1.05);
        CHECK(rise2 < 1.4);
        CHECK(rho_exponent > 0.2);
        CHECK(rho_exponent < 0.8);
        CHECK(fragments[2] > fragments[0]);
    }
}
