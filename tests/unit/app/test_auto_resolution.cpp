// simulation.elements = "auto" and `bake --preview` against the study's reference
// (docs/benchmarks.md, "Model no more than a scene needs"): the presets' automatic resolution
// gives pattern statistics within the texture user's tolerance of the converged reference
// (shown converged in docs/accuracy.md), averaged over seeds, on the plane (mud) and the cylinder
// (bark); the preview's reduced model keeps within its own, looser bounds and really is reduced.
#include "app/bench/study_metrics.hpp"
#include "core/json.hpp"
#include "io/resolution.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"
#include "support/presets.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

/// The texture user's tolerance (docs/benchmarks.md, "Tolerances"; app::stat_tolerances): crack
/// density and fragment area within 5 %, T share within 0.05 of the converged reference, for the
/// seed average. The preview's reduced model keeps the pattern's character within looser,
/// documented bounds (its measured deviations are in docs/benchmarks.md).
const std::vector<std::string> TOLERANCED = {"crack_length_per_area", "mean_fragment_area", "t_junction_fraction"};
struct PreviewBound {
    std::string key;
    double bound; ///< relative for the two sizes, absolute for the T share
};
const std::vector<PreviewBound> PREVIEW_BOUNDS = {
    {"crack_length_per_area", 0.2}, {"mean_fragment_area", 0.6}, {"t_junction_fraction", 0.45}};
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

std::vector<app::StatError> errors(const std::vector<app::StatMap>& runs, const std::string& preset) {
    return app::stat_errors(app::average_stats(runs, app::scales_of(TOLERANCED)), app::embedded_reference().at(preset),
                            TOLERANCED);
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("auto resolution: the presets' statistics are within the texture user's tolerance of the converged "
              "reference, over seeds (plane and cylinder)") {
        for (const char* preset : {"bark", "mud"}) {
            CAPTURE(std::string(preset));
            REQUIRE(test::load(preset).is_auto("simulation.elements"));
            std::vector<app::StatMap> runs;
            // Three seeds for bark; two for mud, whose seed spread is small (the study reference's:
            // crack density 0.7 %, T share 0.004) against the tolerance, and whose run is 11× bark's.
            const std::vector<std::string> seeds = std::string(preset) == "mud"
                                                       ? std::vector<std::string>{"1", "2"}
                                                       : std::vector<std::string>{"1", "2", "3"};
            for (const std::string& seed : seeds)
                runs.push_back(run_stats({"-q", "simulate", preset, "--seed", seed}));
            // A periodic mesh has an even number of triangles: 8889 asked gives 8888.
            CHECK(std::abs(runs.front().at("elements_initial") - double(io::element_count(test::load(preset)).elements))
                  <= 1);
            int compared = 0;
            const std::size_t reference_seeds = app::embedded_reference().at(preset).seeds.size();
            for (const app::StatError& e : errors(runs, preset)) {
                CAPTURE(e.key);
                CAPTURE(e.value);
                CAPTURE(e.mean);
                CAPTURE(e.error);
                if (!e.comparable) continue;
                ++compared;
                // Not shown outside the tolerance: outside it by more than two standard errors of
                // the difference of the two seed means (the refinement study's "not converged",
                // docs/accuracy.md). Mud's seeds agree (crack density 0.4 % per seed): its bound is
                // the tolerance (T share −0.034 at 4 per h²; at 2 per h² −0.081, outside). Bark's
                // tile has about 12 fissures and its seeds scatter by 7 % in crack density, 20 % in
                // fragment area: three seeds against the reference's eight resolve its density to
                // ±9 %, so this cannot tell bark's old 2 per h² (+12 %) from its 8 (+2 % in the
                // refinement study, 4 seeds a count): that decision rests on the study; a gross
                // miss fails here.
                const double se =
                    e.spread
                    * std::sqrt(1.0 / double(runs.size()) + 1.0 / double(std::max<std::size_t>(reference_seeds, 1)));
                CAPTURE(se);
                CHECK(std::abs(e.error) <= app::find_tolerance(e.key)->value + 2 * se);
            }
            CHECK(compared >= 2);
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
            for (const app::StatError& e : errors({s}, preset)) {
                if (!e.comparable) continue;
                CAPTURE(e.key);
                CAPTURE(e.error);
                for (const PreviewBound& b : PREVIEW_BOUNDS)
                    if (b.key == e.key) CHECK(std::abs(e.error) <= b.bound);
            }
        }
    }
}
