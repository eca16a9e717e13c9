// The fracture loops against their references: stiffness refreshed at every step, crack tips
// that wait for the load, and local relaxation cascades against global relaxation.
#include "fracture/fem_split.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using test::LayerSpec;

namespace {

/// A soft 0.2 m mud layer whose top shrinks 6 % per unit time (the bottom 2 %), six times the
/// stiffness refresh tolerance: the stiffness is rebuilt twice before the first crack.
LayerSpec strong_mud(std::uint64_t seed) {
    LayerSpec s;
    s.size = Vec2(0.2, 0.2);
    s.elements = 600;
    s.young = 1e7;
    s.threshold = 2e5;
    s.shrinkage = {0.06, 0.02};
    s.seed = seed;
    return s;
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("loops: shrinkage far above the refresh tolerance rebuilds the stiffness and matches a rebuild at "
              "every step") {
        for (bool split : {true, false}) {
            LayerSpec s = strong_mud(1);
            auto run = [&](const LayerSpec& spec) {
                return split ? test::run_split(spec, 0.6) : test::run_removal(spec, 0.6);
            };
            const auto r = run(s);
            LayerSpec ref = s;
            ref.fem.stiffness_refresh = 0.0; // the reference: K rebuilt at every time step
            const auto e = run(ref);
            CAPTURE(split);
            // 3.6 % of top shrinkage by t = 0.6: the 1 % tolerance is crossed three times.
            CHECK(r.run.stiffness_rebuilds == 3);
            CHECK(e.run.stiffness_rebuilds >= r.run.time_steps / 2);
            REQUIRE(!r.pattern.events.empty());
            REQUIRE(!e.pattern.events.empty());
            // The first crack waits for the same stress: its time within the tolerance's 1 %.
            const double t_r = r.pattern.events.front().time, t_e = e.pattern.events.front().time;
            CHECK(t_r == doctest::Approx(t_e).epsilon(0.01));
            CHECK(r.stats.crack_length_per_area == doctest::Approx(e.stats.crack_length_per_area).epsilon(0.1));
            if (split)
                test::record_claim("refresh",
                                   "stiffness refresh 1e-2 vs rebuilt every step (fem-split, 5 %/t shrinkage)",
                                   "first crack time, relative difference", std::abs(t_r - t_e) / t_e, "< 0.01");
        }
    }

    TEST_CASE("loops: without Griffith's test a tip below threshold waits, and runs on when the load rises") {
        for (mesh::SurfaceKind kind : {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder}) {
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s;
                s.kind = kind;
                s.size = Vec2(0.2, 0.2);
                s.elements = 600;
                s.seed = seed;
                s.growth = {sim::GrowthKind::Anisotropic, 3e-4, 0.0, 0.0}; // stretch around: cracks along v
                test::Layer layer(s);
                fracture::FractureOptions o;
                fracture::SplitOptions split;
                split.griffith = false;
                split.check_invariants = true;
                Rng rng(seed, RngStream::Fracture);
                fracture::RunStats run;
                const auto pattern = fracture::run_fem_split(*layer.model, o, split, rng, &run);
                CAPTURE(std::string(mesh::to_string(kind)));
                CAPTURE(seed);
                REQUIRE(run.splits > 0);
                // At the end no tip is over its threshold: one that was would have run on.
                double worst = 0;
                const auto tips = fracture::crack_tips(*layer.model);
                for (std::size_t t : tips)
                    worst = std::max(worst, fracture::nodal_stress(*layer.model, t).ratio);
                CAPTURE(tips.size());
                CHECK(worst <= 1.0 + 1e-6);
                // ...and some tips did wait and resume: extensions later than the last new fracture
                // before them are tips that stopped for a while.
                std::size_t resumed = 0;
                for (std::size_t i = 1; i < pattern.events.size(); ++i)
                    if (pattern.events[i].kind == "extend" && pattern.events[i].time > pattern.events[i - 1].time)
                        ++resumed;
                CHECK(resumed > 0);
            }
        }
    }
}
