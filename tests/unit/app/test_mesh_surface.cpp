// surface.kind = "mesh" (issue 30, so far): `crackle mesh` reads the artist's model named by the
// preset, sizes an "auto" element count from the model's area and remeshes it; simulate, bake and
// export refuse a model surface with exit 2 until they can grow a layer on one.
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "io/preset.hpp"
#include "mesh/model_surface.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

const fs::path DUCK = "/usr/share/assimp/models/Collada/duck.dae";

/// A preset beside a copy of the duck, naming it relatively.
fs::path duck_preset(const std::string& extra) {
    REQUIRE_MESSAGE(fs::is_regular_file(DUCK), "run scripts/setup (assimp-testmodels)");
    const fs::path dir = test::scratch_dir("mesh-surface");
    fs::copy_file(DUCK, dir / "duck.dae", fs::copy_options::overwrite_existing);
    const fs::path preset = dir / "duck.toml";
    std::ofstream(preset) << "[surface]\nkind = \"mesh\"\nfile = \"duck.dae\"\n" << extra;
    return preset;
}

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("mesh surface: crackle mesh remeshes the preset's model to its element count, well shaped") {
        const fs::path preset = duck_preset("[simulation]\nelements = 3000\n");
        const fs::path json = preset.parent_path() / "duck.json";
        const test::CliResult r = test::run_cli({"-q", "mesh", preset.string(), "--json", json.string()});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        const Json report = Json::parse(read_file(json), json.string());
        CHECK(report.find("surface")->as_string() == "mesh");
        CHECK(report.find("faces")->as_number() == doctest::Approx(3000).epsilon(0.06));
        CHECK(report.find("min_angle_deg")->as_number() > 15.0);

        // "auto" follows the model's area (the duck's 7.0 m²), capped by the map's pixels.
        io::PresetRequest request;
        request.name_or_path = duck_preset("[bake]\nsize = 256\n").string();
        const app::RunPlan plan = app::make_run_plan(io::load_preset(request), {.discretize_only = true});
        REQUIRE(plan.surface.model != nullptr);
        CHECK(plan.elements.automatic);
        CHECK_MESSAGE(contains(plan.elements.reason, "over 7.03 m²"), plan.elements.reason);
        CHECK(plan.elements.elements == 8192); // 256² px / 8 px per element
    }

    TEST_CASE("mesh surface: simulate, bake and export refuse a model surface, and a bad model is named") {
        const fs::path preset = duck_preset("[simulation]\nelements = 1000\n");
        const std::string out = (preset.parent_path() / "out").string();
        for (const std::vector<std::string>& run :
             {std::vector<std::string>{"simulate", preset.string(), "--json", out + "/r.json"},
              {"bake", preset.string(), "--out", out},
              {"export", preset.string(), "--out", out + "/duck.glb"}}) {
            CAPTURE(run[0]);
            const test::CliResult r = test::run_cli(run);
            CHECK(r.code == 2);
            CHECK_MESSAGE(contains(r.err, "cannot yet simulate, bake or export"), r.err);
        }
        CHECK(!fs::exists(preset.parent_path() / "out"));
        const fs::path dir = preset.parent_path();
        std::ofstream(dir / "none.toml") << "[surface]\nkind = \"mesh\"\n";
        test::CliResult r = test::run_cli({"mesh", (dir / "none.toml").string()});
        CHECK(r.code == 2);
        CHECK(contains(r.err, "needs its model"));
        std::ofstream(dir / "gone.toml") << "[surface]\nkind = \"mesh\"\nfile = \"gone.glb\"\n";
        r = test::run_cli({"mesh", (dir / "gone.toml").string()});
        CHECK(r.code == 2);
        CHECK(contains(r.err, "not found"));
        std::ofstream(dir / "junk.obj") << "this is no model\n";
        std::ofstream(dir / "junk.toml") << "[surface]\nkind = \"mesh\"\nfile = \"junk.obj\"\n";
        r = test::run_cli({"mesh", (dir / "junk.toml").string()});
        CHECK(r.code == 2);
        CHECK_MESSAGE(contains(r.err, "surface.file"), r.err);
    }
}
