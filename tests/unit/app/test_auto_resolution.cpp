// simulation.elements = "auto" and `bake --preview` against the study's reference
// (docs/benchmarks.md, "Model no more than a scene needs"): the presets' automatic resolution
// gives pattern statistics within the documented tolerance of the converged reference, averaged
// over seeds, on the plane (mud) and the cylinder (bark); the preview's reduced model keeps
// within its own, looser tolerance and really is reduced.
#include "app/study_metrics.hpp"
#include "core/json.hpp"
#include "io/resolution.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"
#include "support/presets.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

/// The documented tolerances (docs/benchmarks.md, "Model no more than a scene needs"): the
/// distance of a seed average to the reference, in seed spreads. Mud at auto is converged (the
/// study: 0.9 over three seeds; two seeds scatter more); bark sits at 1.7–2.1 at every count
/// below 16k elements, auto's included. The preview keeps crack density and plate size but not
/// mud's T-junctions (no tip sub-model): within five spreads.
double auto_tolerance(const std::string& preset) {
    return preset == "mud" ? 1.5 : 2.5;
}
constexpr double PREVIEW_TOLERANCE = 5.0;

app::StatMap report_stats(const fs::path& json) {
    const Json report = Json::parse(test::slurp(json), json.string());
    app::StatMap s;
    for (const auto& [key, value] : report.members())
        if (value.is_number()) s[key] = value.as_number();
    return s;
}

app::StatMap run_stats(std::vector<std::string> args) {
    const fs::path dir = test::scratch_dir("auto-resolution");
    args.insert(args.end(), {"--json", (dir / "r.json").string()});
    const auto r = test::run_cli(args);
    REQUIRE(r.code == 0);
    return report_stats(dir / "r.json");
}

double distance(const std::vector<app::StatMap>& runs, const std::string& preset) {
    const auto scales = app::pattern_scales(preset);
    return app::pattern_distance(app::average_stats(runs, scales), app::embedded_reference().at(preset), scales);
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("auto resolution: the presets' statistics are within tolerance of the converged reference, over "
              "seeds (plane and cylinder)") {
        for (const char* preset : {"bark", "mud"}) {
            CAPTURE(std::string(preset));
            REQUIRE(test::load(preset).is_auto("simulation.elements"));
            std::vector<app::StatMap> runs;
            for (const char* seed : {"1", "2"})
                runs.push_back(run_stats({"-q", "simulate", preset, "--seed", seed}));
            CHECK(runs.front().at("elements_initial") == double(io::element_count(test::load(preset)).elements));
            const double d = distance(runs, preset);
            CAPTURE(d);
            CHECK(d >= 0);
            CHECK(d <= auto_tolerance(preset));
        }
    }

    TEST_CASE("auto resolution: bake --preview runs the reduced model and keeps the pattern's character") {
        if (!test::gl_context_or_skip()) return;
        for (const char* preset : {"bark", "mud"}) {
            CAPTURE(std::string(preset));
            const fs::path dir = test::scratch_dir("preview");
            const auto r = test::run_cli({"-q", "bake", preset, "--preview", "--out", (dir / "maps").string(), "--json",
                                          (dir / "r.json").string()});
            REQUIRE(r.code == 0);
            const app::StatMap s = report_stats(dir / "r.json");
            const io::Preset full = test::load(preset);
            CHECK(s.at("elements_initial") == double(io::element_count(full, true).elements));
            CHECK(s.at("elements_initial") < double(io::element_count(full).elements) / 4);
            CHECK(s.at("tip_submodels") == 0);
            CHECK(s.at("size") == 512);
            const double d = distance({s}, preset);
            CAPTURE(d);
            CHECK(d <= PREVIEW_TOLERANCE);
        }
    }
}
