#include "core/error.hpp"
#include "fracture/bar1d.hpp"
#include "support/accuracy.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <vector>

using namespace crackle;
namespace bar1d = crackle::fracture::bar1d;

namespace {

/// The digest's numerical check (thesis-digest §2.6.2): K_S = 1, K_A = 50, l₀ = 1, d = 0.02.
const bar1d::Stiffness DIGEST_STIFFNESS{1.0, 50.0};
const bar1d::Segment DIGEST_SEGMENT{1.0, 0.0, 1.02, 1.0};

double discrete_max_tension(int n) {
    const bar1d::DiscreteBar bar = bar1d::uniform_bar(DIGEST_STIFFNESS, n, DIGEST_SEGMENT);
    return bar1d::spring_tensions(bar, bar1d::equilibrium(bar)).maxCoeff();
}

/// Linear background growth of a free bar (Fig. A.2): K_S = 1, K_A = 50, l₀ = 1, g = 1, T_b = 0.01.
bar1d::SimulationOptions growth_options(int n, double duration) {
    bar1d::SimulationOptions o;
    o.stiffness = DIGEST_STIFFNESS;
    o.segments = n;
    o.length = 1.0;
    o.growth_rate = 1.0;
    o.break_tension = 0.01;
    o.duration = duration;
    return o;
}

/// Events come in time order, each at or above the threshold.
void check_events(const bar1d::SimulationResult& r) {
    for (std::size_t k = 0; k < r.events.size(); ++k) {
        CAPTURE(k);
        CHECK(r.events[k].ratio >= 1.0 - 1e-9);
        if (k > 0) CHECK(r.events[k].time >= r.events[k - 1].time);
    }
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("bar1d: discrete maximum tension matches the digest reference values") {
        const std::array<int, 5> springs = {8, 16, 32, 64, 256};
        const std::array<double, 5> reference = {0.0187053, 0.0188021, 0.0188269, 0.0188332, 0.0188351};
        double worst = 0;
        for (std::size_t k = 0; k < springs.size(); ++k) {
            CAPTURE(springs[k]);
            CHECK(std::abs(discrete_max_tension(springs[k]) - reference[k]) < 1e-6);
            worst = std::max(worst, std::abs(discrete_max_tension(springs[k]) - reference[k]));
        }
        const double analytic = bar1d::max_tension_free(DIGEST_STIFFNESS, 1.0, DIGEST_SEGMENT.mismatch());
        CHECK(std::abs(analytic - 0.0188353) < 1e-7);
        test::record_claim("7.3 1D analytic bar", "discrete T_max matches the digest's values (§2.6.2)",
                           "largest |T_max − reference| over 8..256 springs", worst, "< 1e-6");
        test::record_claim("7.3 1D analytic bar", "analytic T_max matches the digest's value (§2.6.2)",
                           "|T_max − 0.0188353|", std::abs(analytic - 0.0188353), "< 1e-7");
    }

    TEST_CASE("bar1d: discrete maximum tension converges to the analytic value at second order") {
        const double analytic = bar1d::max_tension_free(DIGEST_STIFFNESS, 1.0, DIGEST_SEGMENT.mismatch());
        std::vector<double> error;
        for (int n = 8; n <= 256; n *= 2) {
            const double T = discrete_max_tension(n);
            CAPTURE(n);
            CHECK(T < analytic); // the discrete bar is slightly stiffer near its ends
            error.push_back(analytic - T);
        }
        double lowest = 1e300, highest = 0;
        for (std::size_t k = 1; k < error.size(); ++k) {
            const double ratio = error[k - 1] / error[k];
            CAPTURE(k);
            CAPTURE(ratio);
            CHECK(ratio > 3.5);
            CHECK(ratio < 4.5);
            lowest = std::min(lowest, ratio);
            highest = std::max(highest, ratio);
        }
        test::record_claim("A.2", "discrete T_max converges at O(h²) (8 → 256 springs)",
                           "smallest error ratio per halving of h", lowest, "> 3.5 (4 = second order)");
        test::record_claim("A.2", "discrete T_max converges at O(h²) (8 → 256 springs)",
                           "largest error ratio per halving of h", highest, "< 4.5");
    }

    TEST_CASE("bar1d: discrete equilibrium satisfies Eq. A.1 and the free-end equations A.7 and A.8") {
        const int n = 20;
        const bar1d::Segment segment{1.0, 0.3, 1.45, 0.97};
        const bar1d::DiscreteBar bar = bar1d::uniform_bar(DIGEST_STIFFNESS, n, segment);
        const VecX p = bar1d::equilibrium(bar);
        const double h = 1.0 / n;
        const double K_S = DIGEST_STIFFNESS.K_S;
        const double K_A = DIGEST_STIFFNESS.K_A;
        const double rest = segment.lambda * h;
        const auto a = [&](int i) { return segment.a0 + (segment.an - segment.a0) * i * h; };
        const auto spring = [&](int i) { return K_S / h * (p[i + 1] - p[i] - rest); }; // tension of spring i
        CHECK(std::abs(spring(0) - 0.5 * K_A * h * (p[0] - a(0))) < 1e-12);            // Eq. A.7
        CHECK(std::abs(-spring(n - 1) - 0.5 * K_A * h * (p[n] - a(n))) < 1e-12);       // Eq. A.8
        for (int i = 1; i < n; ++i) {
            CAPTURE(i);
            CHECK(std::abs(spring(i) - spring(i - 1) - K_A * h * (p[i] - a(i))) < 1e-12); // Eq. A.1
        }
    }

    TEST_CASE("bar1d: a bar whose rest lengths match the anchor spacing carries no tension") {
        const bar1d::DiscreteBar bar = bar1d::uniform_bar(DIGEST_STIFFNESS, 16, bar1d::Segment{2.0, -0.5, 1.3, 0.9});
        const VecX p = bar1d::equilibrium(bar);
        CHECK(bar1d::spring_tensions(bar, p).cwiseAbs().maxCoeff() < 1e-12);
        for (std::size_t i = 0; i < bar.num_nodes(); ++i)
            CHECK(p[static_cast<Eigen::Index>(i)] == doctest::Approx(bar.anchors[i]));
    }

    TEST_CASE("bar1d: continuous solution satisfies the ODE and the boundary conditions of all four types") {
        const bar1d::Stiffness stiffness{2.0, 30.0};
        const bar1d::Segment segment{1.3, 0.1, 1.5, 0.95}; // d = 0.165 with shrinkage λ = 0.95
        const double l0 = segment.l0;
        const double delta = 1e-4;
        double residual = 0;
        for (const auto type : {bar1d::BoundaryType::FreeFree, bar1d::BoundaryType::LeftFixed,
                                bar1d::BoundaryType::RightFixed, bar1d::BoundaryType::BothFixed}) {
            CAPTURE(static_cast<int>(type));
            const bar1d::Boundary boundary{type, 0.05, 1.52};
            const bar1d::ContinuousSolution s = bar1d::solve_continuous(stiffness, segment, boundary);
            // Eq. A.4: −K_S·p'' + K_A·p − K_A·((a_n − a₀)/l₀·x + a₀) = 0, p'' by central differences
            for (int k = 1; k < 20; ++k) {
                const double x = l0 * k / 20.0;
                CAPTURE(x);
                const double p = bar1d::position(s, x);
                const double p_xx =
                    (bar1d::position(s, x + delta) - 2.0 * p + bar1d::position(s, x - delta)) / (delta * delta);
                const double anchor = (segment.an - segment.a0) / l0 * x + segment.a0;
                CHECK(std::abs(-stiffness.K_S * p_xx + stiffness.K_A * p - stiffness.K_A * anchor) < 1e-5);
                residual =
                    std::max(residual, std::abs(-stiffness.K_S * p_xx + stiffness.K_A * p - stiffness.K_A * anchor));
                // slope() is p' and tension() is K_S·(p' − λ)
                const double p_x = (bar1d::position(s, x + delta) - bar1d::position(s, x - delta)) / (2.0 * delta);
                CHECK(std::abs(bar1d::slope(s, x) - p_x) < 1e-7);
                CHECK(bar1d::tension(s, x)
                      == doctest::Approx(stiffness.K_S * (bar1d::slope(s, x) - segment.lambda)).epsilon(1e-12));
            }
            // Boundary conditions: a free end has p' = λ (zero tension), a fixed end p = Z.
            const bool left_fixed = type == bar1d::BoundaryType::LeftFixed || type == bar1d::BoundaryType::BothFixed;
            const bool right_fixed = type == bar1d::BoundaryType::RightFixed || type == bar1d::BoundaryType::BothFixed;
            if (left_fixed)
                CHECK(std::abs(bar1d::position(s, 0.0) - boundary.Z_L) < 1e-12);
            else
                CHECK(std::abs(bar1d::tension(s, 0.0)) < 1e-12);
            if (right_fixed)
                CHECK(std::abs(bar1d::position(s, l0) - boundary.Z_R) < 1e-12);
            else
                CHECK(std::abs(bar1d::tension(s, l0)) < 1e-12);
        }
        test::record_claim("7.3 1D analytic bar", "the continuous solution satisfies Eq. A.4 (4 boundary types)",
                           "largest residual of −K_S·p'' + K_A·(p − a), p'' by central differences", residual,
                           "< 1e-5");
    }

    TEST_CASE("bar1d: continuous maximum tension is the largest sampled tension for all four types") {
        const bar1d::Stiffness stiffness{1.0, 50.0};
        const bar1d::Segment segment{1.0, 0.0, 1.02, 1.0};
        const std::array<bar1d::Boundary, 5> boundaries = {
            bar1d::Boundary{bar1d::BoundaryType::FreeFree, 0.0, 0.0},
            bar1d::Boundary{bar1d::BoundaryType::LeftFixed, 0.01, 0.0},
            bar1d::Boundary{bar1d::BoundaryType::RightFixed, 0.0, 1.03},
            bar1d::Boundary{bar1d::BoundaryType::BothFixed, -0.01, 1.03},
            bar1d::Boundary{bar1d::BoundaryType::BothFixed, 0.005, 1.015},
        };
        for (const bar1d::Boundary& boundary : boundaries) {
            CAPTURE(static_cast<int>(boundary.type));
            CAPTURE(boundary.Z_L);
            const bar1d::ContinuousSolution s = bar1d::solve_continuous(stiffness, segment, boundary);
            const bar1d::TensionPeak peak = bar1d::max_tension(s);
            CHECK(peak.x >= 0.0);
            CHECK(peak.x <= segment.l0);
            CHECK(peak.tension == doctest::Approx(bar1d::tension(s, peak.x)).epsilon(1e-12));
            double sampled = -1e300;
            for (int k = 0; k <= 4000; ++k)
                sampled = std::max(sampled, bar1d::tension(s, segment.l0 * k / 4000.0));
            CHECK(peak.tension >= sampled - 1e-13);
            CHECK(peak.tension - sampled < 1e-7);
        }
    }

    TEST_CASE("bar1d: free fragment closed forms agree with the general solution") {
        const bar1d::Stiffness stiffness{1.5, 40.0};
        for (const double lambda : {1.0, 0.9}) {
            CAPTURE(lambda);
            const bar1d::Segment segment{0.8, 0.2, 1.05, lambda};
            const double d = segment.mismatch();
            const bar1d::ContinuousSolution s = bar1d::solve_continuous(stiffness, segment, bar1d::Boundary{});
            for (int k = 0; k <= 10; ++k) {
                const double x = segment.l0 * k / 10.0;
                CHECK(bar1d::tension(s, x)
                      == doctest::Approx(bar1d::tension_free(stiffness, segment.l0, d, x)).epsilon(1e-10));
            }
            const bar1d::TensionPeak peak = bar1d::max_tension(s);
            CHECK(peak.x == doctest::Approx(0.5 * segment.l0).epsilon(1e-12));
            CHECK(peak.tension == doctest::Approx(bar1d::max_tension_free(stiffness, segment.l0, d)).epsilon(1e-12));
        }
        // At t* the peak of a fragment growing as a(x, t) = x·(1 + g·t) reaches T_b.
        const double l0 = 0.7, g = 0.3, T_b = 0.02;
        const double t_star = bar1d::break_time_free(stiffness, l0, g, T_b);
        CHECK(bar1d::max_tension_free(stiffness, l0, l0 * g * t_star) == doctest::Approx(T_b).epsilon(1e-12));
        // Short fragments: T_max ≈ K_A·d·l₀/8 when r·l₀ ≪ 1.
        CHECK(bar1d::max_tension_free(stiffness, 0.01, 1e-4) == doctest::Approx(40.0 * 1e-4 * 0.01 / 8).epsilon(1e-3));
    }

    TEST_CASE("bar1d: a fragment cut off by a broken spring is a free fragment ending at the spring midpoint") {
        // Breaking the middle spring of an odd bar leaves two halves of effective length l₀/2 and mismatch d/2.
        const double analytic = bar1d::max_tension_free(DIGEST_STIFFNESS, 0.5, 0.5 * DIGEST_SEGMENT.mismatch());
        std::vector<double> error, profile_error;
        for (const int n : {17, 33, 65, 129}) {
            CAPTURE(n);
            bar1d::DiscreteBar bar = bar1d::uniform_bar(DIGEST_STIFFNESS, n, DIGEST_SEGMENT);
            const auto middle = static_cast<std::size_t>(n / 2);
            bar1d::break_spring(bar, middle);
            const VecX T = bar1d::spring_tensions(bar, bar1d::equilibrium(bar));
            CHECK(T[static_cast<Eigen::Index>(middle)] == 0.0);
            // The whole tension profile follows the continuous one, T(x) at the spring midpoints.
            double profile = 0.0;
            for (std::size_t j = 0; j < middle; ++j) {
                const double x = (static_cast<double>(j) + 0.5) / n;
                profile = std::max(profile, std::abs(T[static_cast<Eigen::Index>(j)]
                                                     - bar1d::tension_free(DIGEST_STIFFNESS, 0.5, 0.01, x)));
            }
            profile_error.push_back(profile);
            const double left = T.head(static_cast<Eigen::Index>(middle)).maxCoeff();
            const double right = T.tail(static_cast<Eigen::Index>(middle)).maxCoeff();
            CHECK(left == doctest::Approx(right).epsilon(1e-9)); // mirror symmetry
            error.push_back(std::abs(analytic - left));
        }
        double slowest = 1e300;
        for (std::size_t k = 1; k < error.size(); ++k) {
            CAPTURE(k);
            CHECK(error[k - 1] / error[k] > 3.5);
            CHECK(error[k - 1] / error[k] < 4.5);
            CHECK(profile_error[k - 1] / profile_error[k] > 3.0);
            slowest = std::min(slowest, profile_error[k - 1] / profile_error[k]);
        }
        CHECK(error.back() < 1e-6);
        CHECK(profile_error.back() < 1e-5);
        test::record_claim("A.4", "discrete matches continuous; the difference vanishes under refinement",
                           "max |T_disc − T_cont| over a broken bar's half, 129 springs", profile_error.back(),
                           "< 1e-5");
        test::record_claim("A.4", "discrete matches continuous; the difference vanishes under refinement",
                           "smallest ratio of max |T_disc − T_cont| per halving of h (17 → 129)", slowest, "> 3");
        test::record_claim("A.4", "discrete matches continuous; the difference vanishes under refinement",
                           "|T_max(disc) − T_max(cont)| of the half-bar, 129 springs", error.back(), "< 1e-6");
    }

    TEST_CASE("bar1d: first break of a free fragment is at its midpoint at the analytic break time") {
        const double t_star = bar1d::break_time_free(DIGEST_STIFFNESS, 1.0, 1.0, 0.01);
        SUBCASE("odd n breaks the middle spring exactly at the midpoint") {
            for (const int n : {65, 257}) {
                CAPTURE(n);
                const bar1d::SimulationResult r = bar1d::simulate(growth_options(n, 0.012));
                REQUIRE(r.events.size() == 1);
                CHECK(r.events[0].spring == static_cast<std::size_t>(n / 2));
                CHECK(r.events[0].position == doctest::Approx(0.5).epsilon(1e-12));
                CHECK(r.events[0].ratio == doctest::Approx(1.0).epsilon(1e-9));
                CHECK(r.events[0].time > t_star); // the discrete peak is slightly lower
                CHECK(r.events[0].time == doctest::Approx(t_star).epsilon(n > 100 ? 1e-5 : 1e-4));
                test::record_claim("A.2", "first break time converges to the analytic t*",
                                   "|t − t*| with " + std::to_string(n) + " springs (t* ≈ 0.0106)",
                                   std::abs(r.events[0].time - t_star),
                                   n > 100 ? "< 1e-5·(1 + t*)" : "< 1e-4·(1 + t*)");
            }
        }
        SUBCASE("even n breaks the lower of the two tied middle springs") {
            for (const int n : {64, 256}) {
                CAPTURE(n);
                const bar1d::SimulationResult r = bar1d::simulate(growth_options(n, 0.012));
                REQUIRE(r.events.size() == 1);
                const double h = 1.0 / n;
                CHECK(r.events[0].spring == static_cast<std::size_t>(n / 2 - 1));
                CHECK(r.events[0].position == doctest::Approx(0.5 - 0.5 * h).epsilon(1e-12));
                CHECK(r.events[0].time == doctest::Approx(t_star).epsilon(n > 100 ? 1e-5 : 1e-3));
            }
        }
        SUBCASE("before t* nothing breaks and the bar is intact") {
            const bar1d::SimulationResult r = bar1d::simulate(growth_options(257, 0.99 * t_star));
            CHECK(r.events.empty());
            CHECK(r.final_time == doctest::Approx(0.99 * t_star));
            CHECK(r.tensions.maxCoeff() < 0.01);
        }
    }

    TEST_CASE("bar1d: the halves of a broken fragment break later in a hierarchical pattern") {
        const int n = 257;
        const double h = 1.0 / n;
        const bar1d::SimulationResult r = bar1d::simulate(growth_options(n, 0.05));
        check_events(r);
        REQUIRE(r.events.size() == 7); // 1 + 2 + 4 breaks before the fourth generation
        const auto& e = r.events;
        CHECK(e[0].position == doctest::Approx(0.5));
        // Second generation: the halves split near l₀/4 and 3l₀/4, at t*(l₀/2) > t*(l₀).
        const double t2 = bar1d::break_time_free(DIGEST_STIFFNESS, 0.5, 1.0, 0.01);
        for (int k = 1; k <= 2; ++k) {
            CAPTURE(k);
            CHECK(e[k].time > e[0].time);
            CHECK(e[k].time == doctest::Approx(t2).epsilon(1e-3));
            CHECK(std::abs(std::abs(e[k].position - 0.5) - 0.25) < 1.5 * h);
        }
        // Third generation: quarters, later still.
        const double t3 = bar1d::break_time_free(DIGEST_STIFFNESS, 0.25, 1.0, 0.01);
        std::vector<double> positions;
        for (int k = 3; k <= 6; ++k) {
            CAPTURE(k);
            CHECK(e[k].time > std::max(e[1].time, e[2].time));
            CHECK(e[k].time == doctest::Approx(t3).epsilon(0.02)); // quarters differ by ±h in length
            positions.push_back(e[k].position);
        }
        std::sort(positions.begin(), positions.end());
        for (std::size_t k = 0; k < positions.size(); ++k) {
            CAPTURE(k);
            CHECK(std::abs(positions[k] - (0.125 + 0.25 * static_cast<double>(k))) < 1.5 * h);
        }
        // Between generations the break time grows: t*(l₀/4)/t*(l₀/2) > t*(l₀/2)/t*(l₀) > 1.
        CHECK(t3 / t2 > t2 / e[0].time);
    }

    TEST_CASE("bar1d: shrinkage gives the same break sequence as growth with the same mismatch") {
        // d(t) = l₀·g·t with growth, d(t) = l₀·s·t with shrinkage: equal for g = s.
        bar1d::SimulationOptions growth = growth_options(64, 0.2);
        bar1d::SimulationOptions shrinkage = growth;
        shrinkage.growth_rate = 0.0;
        shrinkage.shrinkage_rate = 1.0;
        const bar1d::SimulationResult a = bar1d::simulate(growth);
        const bar1d::SimulationResult b = bar1d::simulate(shrinkage);
        check_events(a);
        check_events(b);
        REQUIRE(a.events.size() > 10);
        REQUIRE(a.events.size() == b.events.size());
        for (std::size_t k = 0; k < a.events.size(); ++k) {
            CAPTURE(k);
            CHECK(a.events[k].spring == b.events[k].spring);
            CHECK(a.events[k].position == b.events[k].position);
            CHECK(a.events[k].time == doctest::Approx(b.events[k].time).epsilon(1e-9));
        }
        CHECK((a.tensions - b.tensions).cwiseAbs().maxCoeff() < 1e-12);
        test::record_claim("1D growth≡shrinkage", "growth and shrinkage with equal mismatch break alike (1D bar)",
                           "largest tension difference at the end", (a.tensions - b.tensions).cwiseAbs().maxCoeff(),
                           "< 1e-12 (and the same springs in the same order)");
        // ... and the first break still follows t* with g replaced by s.
        CHECK(b.events[0].time
              == doctest::Approx(bar1d::break_time_free(DIGEST_STIFFNESS, 1.0, 1.0, 0.01)).epsilon(1e-3));
    }

    TEST_CASE("bar1d: automatic subdivision lets a bar with growing rest lengths keep breaking") {
        bar1d::SimulationOptions o = growth_options(8, 40.0);
        o.rest_growth_rate = 0.95; // mismatch rate g − q = 0.05
        // Fixed subdivision (Fig. A.3a): at most one crack per sub-segment.
        const bar1d::SimulationResult fixed = bar1d::simulate(o);
        check_events(fixed);
        CHECK(fixed.events.size() <= 8);
        CHECK(fixed.bar.num_springs() == 8);
        CHECK(fixed.events.back().time < 1.0); // then nothing is left to break

        // Automatic refinement (Fig. A.3b): a sub-segment splits once its rest length reaches 1.2·h₀.
        o.max_rest_length = 1.2 / 8;
        const bar1d::SimulationResult refined = bar1d::simulate(o);
        check_events(refined);
        CHECK_FALSE(refined.capped);
        CHECK(refined.subdivisions > 0);
        CHECK(refined.bar.num_springs() == 8 + refined.subdivisions);
        CHECK(refined.events.size() > 8);
        CHECK(refined.events.back().time > 0.5 * o.duration); // still breaking late in the run
        // Subdivision keeps the material: nodes stay ordered and span [0, l₀].
        CHECK(refined.bar.reference.front() == 0.0);
        CHECK(refined.bar.reference.back() == doctest::Approx(1.0).epsilon(1e-15));
        for (std::size_t j = 0; j < refined.bar.num_springs(); ++j) {
            CAPTURE(j);
            CHECK(refined.bar.size(j) > 0.0);
            if (!refined.bar.broken[j])
                CHECK(refined.bar.rest[j] < o.max_rest_length);
            else
                CHECK(refined.tensions[static_cast<Eigen::Index>(j)] == 0.0);
        }
    }

    TEST_CASE("bar1d: simulate rejects bad options and discrete solves need anchors") {
        bar1d::SimulationOptions o = growth_options(8, 1.0);
        o.break_tension = 0.0;
        CHECK_THROWS_AS(bar1d::simulate(o), InputError);
        o = growth_options(8, 2.0);
        o.shrinkage_rate = 0.6; // rest lengths would reach zero at t = 1/0.6
        CHECK_THROWS_AS(bar1d::simulate(o), InputError);
        o = growth_options(0, 1.0);
        CHECK_THROWS_AS(bar1d::simulate(o), InputError);
        bar1d::DiscreteBar bar = bar1d::uniform_bar(DIGEST_STIFFNESS, 4, DIGEST_SEGMENT);
        bar.reference[2] = bar.reference[1]; // a sub-segment of size 0 has infinite stiffness
        CHECK_THROWS_AS(bar1d::equilibrium(bar), NumericError);
        bar = bar1d::uniform_bar(DIGEST_STIFFNESS, 4, DIGEST_SEGMENT);
        bar.stiffness.K_A = 0.0; // a free bar without anchors floats
        CHECK_THROWS_AS(bar1d::equilibrium(bar), InvariantError);
    }
}
