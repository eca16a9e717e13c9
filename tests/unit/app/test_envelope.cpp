// Stability-envelope rows (docs/benchmarks.md, "Stability envelope") that are not failures but
// could hide one: the solver and relaxation knobs at their loosest legal values must not move
// the pattern silently, on the plane (mud) and on the cylinder (bark).
#include "core/json.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

Json simulate(const std::string& preset, const std::string& method, const std::vector<std::string>& extra) {
    const fs::path dir = test::scratch_dir("envelope");
    std::vector<std::string> args = {"-q",
                                     "simulate",
                                     preset,
                                     "--set",
                                     "simulation.method=" + method,
                                     "--set",
                                     "simulation.elements=800",
                                     "--json",
                                     (dir / "r.json").string()};
    if (method == "fem-split") args.insert(args.end(), {"--set", "simulation.tip_submodel=0"});
    for (const auto& e : extra)
        args.insert(args.end(), {"--set", e});
    const auto r = test::run_cli(args);
    REQUIRE(r.code == 0);
    return Json::parse(test::slurp(dir / "r.json"), "r.json");
}

double number(const Json& j, const char* key) {
    return j.find(key)->as_number();
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("envelope: the loosest local relaxation and solver tolerances keep the crack pattern (plane and "
              "cylinder)") {
        for (const char* preset : {"mud", "bark"})
            for (const char* method : {"fem-split", "fem-remove", "graph-fem"}) {
                CAPTURE(std::string(preset));
                CAPTURE(std::string(method));
                const Json base = simulate(preset, method, {});
                const Json loose_local =
                    simulate(preset, method, {"simulation.local_tolerance=0.5", "simulation.drift_tolerance=1"});
                const Json loose_solver = simulate(preset, method, {"simulation.solver_tolerance=1e-4"});
                REQUIRE(number(base, "crack_length_per_area") > 0);
                for (const Json* other : {&loose_local, &loose_solver}) {
                    // The envelope sweep measured at most 3 % (docs/benchmarks.md); the seed-to-seed
                    // spread of these statistics at 800 elements is larger.
                    CHECK(number(*other, "crack_length_per_area")
                          == doctest::Approx(number(base, "crack_length_per_area")).epsilon(0.06));
                    CHECK(std::abs(number(*other, "fragments") - number(base, "fragments"))
                          <= 0.12 * number(base, "fragments") + 2);
                }
            }
        // 1e-3 let fem-remove's re-solves stop before a removal had spread its load (bark lost half
        // its crack length): the key now refuses it, naming the limit.
        const auto r = test::run_cli({"-q", "simulate", "bark", "--set", "simulation.solver_tolerance=0.001"});
        CHECK(r.code == 2);
        CHECK(r.err.find("simulation.solver_tolerance") != std::string::npos);
        CHECK(r.err.find("0.0001") != std::string::npos);
    }

    TEST_CASE("envelope: a poorly shaped starting mesh is reported with its figure (plane, cylinder, sphere)") {
        // Uniformly random points (no repulsion) leave a few % of slivers: fem-remove's crack
        // density rose 22 % and graph-fem lost a third of its fragments on them. The run goes on,
        // with a warning that names the share; the default mesh gives none.
        for (const char* preset : {"mud", "bark", "fruit"}) {
            CAPTURE(std::string(preset));
            const auto poor = test::run_cli({"simulate", preset, "--set", "simulation.method=fem-remove", "--set",
                                             "simulation.elements=1200", "--set", "simulation.repulsion_iterations=0"});
            CHECK(poor.code == 0);
            CHECK(poor.err.find("% of its triangles below 10 degrees") != std::string::npos);
            const auto good = test::run_cli(
                {"simulate", preset, "--set", "simulation.method=fem-remove", "--set", "simulation.elements=1200"});
            CHECK(good.code == 0);
            CHECK(good.err.find("below 10 degrees") == std::string::npos);
        }
    }

    TEST_CASE("envelope: a mass-spring layer too thin for its force tolerance fails with exit 3 and its numbers") {
        // 0.1 mm of mud: the Newton force tolerance sits near round-off; the run must say so
        // (largest force against the wanted one) and write nothing, never finish silently.
        const fs::path json = test::scratch_dir("envelope-thin") / "r.json";
        const auto r = test::run_cli({"simulate", "mud", "--set", "simulation.method=mass-spring", "--set",
                                      "simulation.elements=800", "--set", "material.thickness=[0.0001,0.0001]",
                                      "--json", json.string()});
        CHECK(r.code == 3);
        CHECK(r.err.find("largest force") != std::string::npos);
        CHECK(r.err.find("wanted") != std::string::npos);
        CHECK(!fs::exists(json));
    }

    TEST_CASE("envelope: an auxetic layer (nu = -0.9) under uniform shrinkage stays below the thin-film threshold "
              "and does not crack, for every FEM method") {
        // σ = E·ε/(1 − ν) with ν = −0.9 is 2.7× smaller than at ν = 0.3: mud's shrinkage of 0.3 %
        // gives 1.6e4 Pa against the 2e4 Pa threshold. (Under mud's top/bottom gradient the
        // single wedge through the thickness overstates the top stress and cracks it: an open
        // row of the envelope, docs/benchmarks.md.)
        for (const char* method : {"fem-split", "fem-remove", "graph-fem"}) {
            CAPTURE(std::string(method));
            const Json r = simulate("mud", method,
                                    {"material.poisson_ratio=-0.9", "material.shrinkage=[0.003,0.003]",
                                     "variation.threshold_stress.amplitude=0"});
            CHECK(number(r, "fracture_events") == 0);
        }
    }
}
