// Thesis claims of Fig. A.3 about the 1D bar (Appendix A): fragments split at their midpoints,
// generation after generation, with break times in a geometric progression; automatic
// subdivision lets the splitting go on past the initial resolution.

#include "fracture/bar1d.hpp"
#include "support/accuracy.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace crackle;
namespace bar1d = crackle::fracture::bar1d;

namespace {

/// A free bar of length 1 on a linearly growing background (g = 1), T_b = 0.01, stopped after
/// the first `generations` generations of breaks (2^G − 1 events).
bar1d::SimulationOptions bar(double K_A, int segments, int generations) {
    bar1d::SimulationOptions o;
    o.stiffness = {1.0, K_A};
    o.segments = segments;
    o.length = 1.0;
    o.growth_rate = 1.0;
    o.break_tension = 0.01;
    o.duration = 1e6;
    o.max_events = (std::size_t(1) << generations) - 1;
    return o;
}

/// Every event against the fragment it broke (between the breaks before it and the bar's
/// ends): distance from the fragment's midpoint and relative deviation of its time from the
/// continuous model's break time of a free fragment of that length (digest §2.6.2).
struct Generations {
    double worst_midpoint = 0;                    ///< largest |position − fragment midpoint| (L)
    double worst_time = 0;                        ///< largest |t − t*(fragment)| / t*(fragment)
    bool hierarchical = true;                     ///< every generation breaks after all of the previous one
    std::vector<double> mean_time, analytic_time; ///< per generation: mean break time, t*(1/2^k)
};

Generations generations(const bar1d::SimulationOptions& o, const bar1d::SimulationResult& r) {
    Generations g;
    const double rate = o.growth_rate - o.rest_growth_rate + o.shrinkage_rate;
    std::vector<double> breaks{0.0, o.length};
    for (const bar1d::BreakEvent& e : r.events) {
        const auto it = std::upper_bound(breaks.begin(), breaks.end(), e.position);
        const double a = *(it - 1), b = *it;
        g.worst_midpoint = std::max(g.worst_midpoint, std::abs(e.position - 0.5 * (a + b)));
        const double t_star = bar1d::break_time_free(o.stiffness, b - a, rate, o.break_tension);
        g.worst_time = std::max(g.worst_time, std::abs(e.time - t_star) / t_star);
        breaks.insert(it, e.position);
    }
    double last_end = 0;
    for (std::size_t k = 0; (std::size_t(2) << k) - 1 <= r.events.size(); ++k) {
        const std::size_t lo = (std::size_t(1) << k) - 1, hi = (std::size_t(2) << k) - 1;
        double sum = 0, first = INFINITY, last = 0;
        for (std::size_t i = lo; i < hi; ++i) {
            sum += r.events[i].time;
            first = std::min(first, r.events[i].time);
            last = std::max(last, r.events[i].time);
        }
        g.hierarchical = g.hierarchical && first > last_end;
        last_end = last;
        g.mean_time.push_back(sum / double(hi - lo));
        g.analytic_time.push_back(
            bar1d::break_time_free(o.stiffness, o.length / double(std::size_t(1) << k), rate, o.break_tension));
    }
    return g;
}

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("claims A.3: fragments split at their midpoints, break times grow by 4 per generation once fragments "
              "are shorter than the decay length") {
        // A free fragment of length l breaks at its midpoint at t* = T_b / (K_S·g·(1 − sech(r·l/2)))
        // (digest §2.6.2). For r·l ≪ 1, t* ∝ 1/l², so halving the fragments multiplies the
        // break time by 4: a geometric progression. For r·l ≫ 1 (fragments longer than the
        // decay length 1/r) t* hardly depends on l, so the ratio starts near 1 and rises to 4.
        // A 1024-spring bar, 6 generations (63 breaks), r = 1 (r·l ≤ 1) and r = √50 (the digest's bar).
        for (const double K_A : {1.0, 50.0}) {
            CAPTURE(K_A);
            const bar1d::SimulationOptions o = bar(K_A, 1024, 6);
            const bar1d::SimulationResult r = bar1d::simulate(o);
            REQUIRE(r.events.size() == 63);
            const Generations g = generations(o, r);
            REQUIRE(g.mean_time.size() == 6);
            const double h = 1.0 / 1024;
            double worst_ratio = 0, worst_geometric = 0;
            for (std::size_t k = 1; k < g.mean_time.size(); ++k) {
                const double ratio = g.mean_time[k] / g.mean_time[k - 1];
                const double analytic = g.analytic_time[k] / g.analytic_time[k - 1];
                CAPTURE(k);
                CAPTURE(ratio);
                worst_ratio = std::max(worst_ratio, std::abs(ratio - analytic) / analytic);
                if (k >= 2) worst_geometric = std::max(worst_geometric, std::abs(ratio - 4.0) / 4.0);
            }
            const double first_ratio = g.mean_time[1] / g.mean_time[0];
            const double last_ratio = g.mean_time[5] / g.mean_time[4];
            if (K_A == 1.0) {
                test::record_claim("A.3", "every fragment splits at its midpoint",
                                   "max |break - fragment midpoint| / spring size, 63 breaks", g.worst_midpoint / h,
                                   "<= 0.5");
                test::record_claim("A.3", "break time of each fragment (continuous model)",
                                   "max |t - t*(fragment length)| / t*", g.worst_time, "< 1e-3");
                test::record_claim("A.3", "break times per generation: geometric progression",
                                   "max over generations 2-5 of |t_k/t_(k-1) - 4| / 4 (r = 1)", worst_geometric,
                                   "< 0.03");
                test::record_claim("A.3", "generation ratio vs continuous model",
                                   "max |ratio - analytic ratio| / analytic (r = 1)", worst_ratio, "< 0.01");
                CHECK(worst_geometric < 0.03);
            } else {
                // Long fragments first: far from geometric at the start, approaching 4.
                test::record_claim("A.3", "break times per generation (r = sqrt 50, fragments longer than 1/r)",
                                   "t_1/t_0 (first generation ratio)", first_ratio, "< 2");
                test::record_claim("A.3", "break times per generation (r = sqrt 50)", "t_5/t_4 (last ratio)",
                                   last_ratio, "> 3.8");
                test::record_claim("A.3", "generation ratio vs continuous model",
                                   "max |ratio - analytic ratio| / analytic (r = sqrt 50)", worst_ratio, "< 0.01");
                CHECK(first_ratio < 2.0);
                CHECK(last_ratio > 3.8);
                CHECK(last_ratio < 4.0);
            }
            CHECK(g.hierarchical);
            CHECK(g.worst_midpoint <= 0.5 * h + 1e-12);
            CHECK(g.worst_time < 1e-3);
            CHECK(worst_ratio < 0.01);
        }
    }

    TEST_CASE("claims A.3 (Fig. A.3b): with automatic subdivision the splitting goes on past the initial resolution") {
        // 16 sub-segments whose rest lengths grow (q = 0.5, so the mismatch grows at g − q = 0.5)
        // and split in two whenever they reach 1/16: a fixed bar of 16 springs can break at most
        // 16 times; this one breaks 31 times (5 generations), still at the midpoints and in
        // time order by generation. Broken springs are never subdivided, so a fragment's ends
        // stay at the resolution of the time it broke (1/32): as fragments shrink towards that
        // size, their break times drift late (a fifth at 1/16), which the tolerances follow.
        bar1d::SimulationOptions o = bar(1.0, 16, 5);
        o.rest_growth_rate = 0.5;
        o.max_rest_length = 1.0001 / 16;
        const bar1d::SimulationResult r = bar1d::simulate(o);
        CHECK(r.capped); // stopped at the 31st break, on purpose
        REQUIRE(r.events.size() == 31);
        CHECK(r.subdivisions > 0);
        const Generations g = generations(o, r);
        REQUIRE(g.mean_time.size() == 5);
        double worst_early = 0;
        for (std::size_t k = 0; k < 3; ++k)
            worst_early = std::max(worst_early, std::abs(g.mean_time[k] - g.analytic_time[k]) / g.analytic_time[k]);
        const double last_ratio = g.mean_time[4] / g.mean_time[3];
        test::record_claim("A.3", "unbounded repetition with auto-subdivision",
                           "breaks of a bar that starts with 16 springs", double(r.events.size()), "== 31");
        test::record_claim("A.3", "every fragment splits at its midpoint (auto-subdivision)",
                           "max |break - fragment midpoint| (initial spring = 1/16)", g.worst_midpoint, "<= 1/64");
        test::record_claim("A.3", "break times per generation (auto-subdivision)",
                           "max over generations 0-2 of |mean t - t*| / t*", worst_early, "< 0.05");
        test::record_claim("A.3", "break times per generation (auto-subdivision)",
                           "max over all breaks of |t - t*(fragment)| / t* (drifts late)", g.worst_time, "< 0.3");
        test::record_claim("A.3", "break times per generation (auto-subdivision)", "t_4/t_3", last_ratio,
                           "in [3.8, 4.5]");
        CHECK(g.hierarchical);
        CHECK(g.worst_midpoint <= 1.0 / 64 + 1e-12);
        CHECK(worst_early < 0.05);
        CHECK(g.worst_time < 0.3);
        CHECK(last_ratio > 3.8);
        CHECK(last_ratio < 4.5);
    }
}
