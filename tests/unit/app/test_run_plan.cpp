// The run plan (issue 29): the preset and the command line resolved once into everything a run
// reads. The flags are typed values of their keys with the flag as their source; the plan holds
// the method made with its options, the budget estimate, the cache key, the output names and
// maps, and the record the report writes as `settings`.
#include "app/run/bake_run.hpp"
#include "app/run/run_budget.hpp"
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "fracture/method.hpp"
#include "io/preset.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>

using namespace crackle;

namespace {

io::PresetRequest mud(std::vector<std::string> overrides = {}) {
    io::PresetRequest r;
    r.name_or_path = "mud";
    r.overrides = std::move(overrides);
    return r;
}

app::RunPlan plan_of(const io::PresetRequest& request, const app::PlanRequest& how = {}) {
    return app::make_run_plan(io::load_preset(request), how);
}

double setting(const app::RunPlan& plan, const std::string& key) {
    const Json* v = plan.record.settings.find(key);
    REQUIRE(v != nullptr);
    return v->as_number();
}

std::string setting_text(const app::RunPlan& plan, const std::string& key) {
    const Json* v = plan.record.settings.find(key);
    REQUIRE(v != nullptr);
    return v->as_string();
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("run plan: --size, --maps, --bit-depth and --preview are typed values of their keys, checked, "
              "their source the flag") {
        app::BakeFlags flags;
        flags.size = "96x48";
        flags.maps = "Color,Displacement";
        flags.bit_depth = "Displacement=16";
        const app::RunPlan plan = plan_of(app::with_bake_flags(mud({"bake.maps=\"Color\""}), flags), {.bake = true});
        CHECK(plan.map.width == 96);
        CHECK(plan.map.height == 48);
        CHECK(setting(plan, "bake.size") == 96);
        CHECK(setting(plan, "bake.size_v") == 48);
        // --maps is written after the --set: the flag wins, as on the command line.
        REQUIRE(plan.output.maps.size() == 2);
        CHECK(plan.output.maps[0].name == "Color");
        CHECK(plan.output.maps[1].name == "Displacement");
        CHECK(plan.output.maps[1].bits == 16);
        CHECK(plan.record.where("bake.size") == "--size: bake.size");
        CHECK(plan.record.where("bake.maps") == "--maps: bake.maps");
        CHECK(plan.record.where("bake.samples") == "bake.samples (mud)"); // a default: the preset to edit

        // The batch puts --maps under each variant's own set (FlagValue::at).
        app::BakeFlags under;
        under.maps = "ORM";
        under.at = 0;
        const app::RunPlan batch = plan_of(app::with_bake_flags(mud({"bake.maps=\"Color\""}), under));
        REQUIRE(batch.output.maps.size() == 1);
        CHECK(batch.output.maps[0].name == "Color");

        // --preview: 512 px and 2 samples, under what --set says.
        app::BakeFlags preview;
        preview.preview = true;
        const app::RunPlan quick = plan_of(app::with_bake_flags(mud(), preview), {.preview = true});
        CHECK(setting(quick, "bake.size") == 512);
        CHECK(setting(quick, "bake.samples") == 2);
        CHECK(quick.bake.samples == 2);
        const app::RunPlan set = plan_of(app::with_bake_flags(mud({"bake.size=256"}), preview), {.preview = true});
        CHECK(set.map.width == 256);

        // Bad flags are refused naming the flag.
        app::BakeFlags bad;
        bad.size = "64y32";
        CHECK_THROWS_WITH_AS(app::with_bake_flags(mud(), bad), doctest::Contains("--size 64y32"), InputError);
        bad = {};
        bad.maps = "Colour";
        CHECK_THROWS_WITH_AS(plan_of(app::with_bake_flags(mud(), bad)), doctest::Contains("--maps"), InputError);
        bad = {};
        bad.size = "20000";
        CHECK_THROWS_AS(app::with_bake_flags(mud(), bad), InputError);
    }

    TEST_CASE("run plan: it holds the method with its options, the estimate, the cache key and the record the "
              "report writes as settings") {
        const io::Preset preset = io::load_preset(mud({"simulation.elements=600"}));
        const app::RunPlan plan = app::make_run_plan(preset);
        REQUIRE(plan.runner != nullptr);
        REQUIRE(plan.method != nullptr);
        CHECK(plan.method->name == preset.text("simulation.method"));
        CHECK(plan.bytes_per_element == doctest::Approx(plan.method->bytes_per_element(preset)));
        CHECK(plan.estimate.bytes == doctest::Approx(app::estimate_run(plan).bytes));
        CHECK(app::make_run_plan(preset, {.bake = true}).estimate.bytes > plan.estimate.bytes);

        // The cache key: the same for the same simulation, whatever the bake; new for a new one.
        auto key = [](std::vector<std::string> overrides) {
            overrides.push_back("simulation.elements=600");
            return plan_of(mud(overrides)).simulation_key;
        };
        CHECK(plan.simulation_key == key({}));
        CHECK(key({"bake.size=256", "bake.crack_depth=0.5", "post.curl=0.5"}) == plan.simulation_key);
        CHECK(key({"material.toughness=3"}) != plan.simulation_key);
        CHECK(key({"simulation.seed=9"}) != plan.simulation_key);

        // The record: every key with its value, an auto count as the number used.
        CHECK(plan.record.preset == "mud");
        CHECK(plan.record.settings.members().size() == preset.values().size());
        const app::RunPlan automatic = plan_of(mud({"bake.size=256"}));
        CHECK(automatic.elements.automatic);
        CHECK(setting(automatic, "simulation.elements") == automatic.elements.elements);
        CHECK(setting_text(plan, "simulation.method") == plan.method->name);
        CHECK(plan.record.toml == preset.to_toml());

        // What `--json` reports as settings is the plan's record.
        const std::filesystem::path json =
            std::filesystem::path(std::getenv("CRACKLE_TEST_OUTPUT") ? std::getenv("CRACKLE_TEST_OUTPUT") : "/tmp")
            / "run-plan-report.json";
        const test::CliResult r = test::run_cli(
            {"-q", "simulate", "mud", "--set", "simulation.elements=600", "--no-cache", "--json", json.string()});
        REQUIRE(r.code == 0);
        const Json report = Json::parse(read_file(json), json.string());
        REQUIRE(report.find("settings") != nullptr);
        CHECK(report.find("settings")->dump() == plan.record.settings.dump());
    }
}
