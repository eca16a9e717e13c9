/// A fracture method is its folder and one registry entry (issue 29): a method registered only
/// here, with a key, a memory figure, a preview reduction and a study variant of its own, reaches
/// the preset schema and its reference, the run, the report, the budget, the preview and the study
/// without a line of the app naming it. And every built-in method gives what the app asks of it.
#include "app/bench/study.hpp"
#include "app/bench/study_plan.hpp"
#include "app/run/bake_run.hpp"
#include "app/run/pipeline.hpp"
#include "app/run/run_budget.hpp"
#include "core/error.hpp"
#include "fracture/method.hpp"
#include "fracture/toolkit/fem_method.hpp"
#include "fracture/toolkit/fem_pattern.hpp"
#include "io/preset.hpp"
#include "io/preset_schema.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <algorithm>

using namespace crackle;
using test::contains;

namespace {

constexpr double STILL_BYTES_PER_ELEMENT = 1.0e6;

/// A method that grows the layer and never cracks it: the smallest honest method.
class Still : public fracture::Method {
public:
    explicit Still(double knob) : m_knob(knob) {}
    fracture::MethodResult run(const fracture::MethodInputs& in, StepTimes& times) const override {
        return fracture::run_on_wedge_layer(in, times, [&](sim::FemModel& model, Rng&, fracture::MethodResult& r) {
            r.pattern = fracture::pattern_from_model(model, "test-still", r.elements_initial);
            r.details["knob"] = m_knob;
            r.summary = "still        no cracks";
        });
    }

private:
    double m_knob;
};

fracture::MethodInfo still_method() {
    fracture::MethodInfo info;
    info.name = "test-still";
    info.description = "test-still (a test's method: never cracks)";
    info.keys = {keys::number("simulation", "still_knob", 1.0, "", 0.0, 10.0, "test-still only: a knob.")};
    info.make = [](const Settings& s) { return std::make_unique<Still>(s.number("simulation.still_knob")); };
    info.bytes_per_element = [](const Settings&) { return STILL_BYTES_PER_ELEMENT; };
    info.preview_overrides = {"simulation.still_knob=7"};
    info.study = {{"test-still-loud", {"simulation.still_knob=9"}, 2.0, 1000}};
    return info;
}

io::Preset still_preset(std::vector<std::string> more = {}) {
    io::PresetRequest request{"mud", {"simulation.method=test-still", "simulation.elements=400"}};
    request.overrides.insert(request.overrides.end(), more.begin(), more.end());
    return io::load_preset(request);
}

} // namespace

TEST_CASE("registry: a method registered in one place reaches the schema, run, report, budget, preview and study") {
    REQUIRE(io::find_key("simulation.still_knob") == nullptr);
    {
        const fracture::ScopedMethod added(still_method());

        // The schema: its name is a simulation.method value, its key is checked like any other
        // and documented under it.
        const KeySpec* method = io::find_key("simulation.method");
        REQUIRE(method != nullptr);
        CHECK(std::count(method->choices.begin(), method->choices.end(), "test-still") == 1);
        const KeySpec* knob = io::find_key("simulation.still_knob");
        REQUIRE(knob != nullptr);
        CHECK(knob->group == "test-still");
        CHECK(contains(io::schema_markdown(), "still_knob"));
        CHECK_THROWS_AS(still_preset({"simulation.still_knob=11"}), InputError);

        // The run and its report.
        const io::Preset preset = still_preset({"simulation.still_knob=3"});
        const app::RunPlan plan = app::make_run_plan(preset);
        StepTimes times;
        const app::SimulationResult r = app::run_simulation(plan, times);
        CHECK(r.pattern.method == "test-still");
        CHECK(r.pattern.events.empty());
        CHECK(r.elements_initial >= 300);
        REQUIRE(r.details.find("knob") != nullptr);
        CHECK(r.details.find("knob")->as_number() == doctest::Approx(3.0));
        const test::CliResult cli = test::run_cli({"-q", "simulate", "mud", "--set", "simulation.method=test-still",
                                                   "--set", "simulation.elements=400", "--no-cache"});
        CHECK(cli.code == 0);

        // The budget takes its memory figure, not another method's.
        const app::RunEstimate& e = plan.estimate;
        const double elements = static_cast<double>(plan.elements.elements);
        CHECK(e.bytes == doctest::Approx(64.0 * 1024 * 1024 + elements * STILL_BYTES_PER_ELEMENT));
        CHECK(e.memory_key == "simulation.elements");

        // The preview applies its reduction (and the preview's element count).
        const app::RunPlan preview = app::make_run_plan(preset, {.preview = true});
        CHECK(preview.record.settings.find("simulation.still_knob")->as_number() == doctest::Approx(7.0));
        CHECK(preview.elements.elements <= plan.elements.elements);
        CHECK(preview.elements.elements == preview.record.settings.find("simulation.elements")->as_number());

        // The study lists its variant, runs it with its overrides and stops at its largest count.
        const std::vector<std::string> names = app::study_methods();
        CHECK(std::count(names.begin(), names.end(), "test-still-loud") == 1);
        const auto runs = app::study_plan({"mud"}, {"test-still-loud"}, 1, false);
        REQUIRE(!runs.empty());
        for (const app::StudyRun& run : runs) {
            CHECK(run.elements <= 1000);
            CHECK(std::count(run.overrides.begin(), run.overrides.end(), "simulation.method=test-still") == 1);
            CHECK(std::count(run.overrides.begin(), run.overrides.end(), "simulation.still_knob=9") == 1);
        }
    }
    // Gone with its scope: the schema no longer knows it.
    CHECK(io::find_key("simulation.still_knob") == nullptr);
    CHECK_THROWS_AS(still_preset(), InputError);
}

TEST_CASE("registry: every built-in method gives a memory figure and its study variants, uniquely named") {
    io::PresetRequest request;
    request.name_or_path = "mud";
    const io::Preset mud = io::load_preset(request);
    std::vector<std::string> variants;
    for (const fracture::MethodInfo& m : fracture::methods()) {
        CAPTURE(m.name);
        REQUIRE(m.bytes_per_element);
        const double bytes = m.bytes_per_element(mud);
        CHECK(bytes > 1e3); // a wedge element's stiffness and factor alone are kilobytes
        CHECK(bytes < 1e5);
        CHECK(!m.study.empty());
        for (const fracture::StudyVariant& v : m.study) {
            variants.push_back(v.name);
            CHECK(v.cost > 0);
        }
        // Its preview overrides are keys of its own or common keys the schema knows.
        for (const std::string& o : m.preview_overrides)
            CHECK(io::find_key(o.substr(0, o.find('='))) != nullptr);
    }
    std::vector<std::string> sorted = variants;
    std::sort(sorted.begin(), sorted.end());
    CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    CHECK(variants == app::study_methods());
}
