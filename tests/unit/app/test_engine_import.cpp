// Exported meshes load upright in an engine: three.js's GLTFLoader (+Y up, like Unity, Godot and
// Unreal's glTF importers) reads the .glb of a mud tile (plane) and a bark trunk (cylinder).
#include "core/json.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <regex>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

struct Loaded {
    double x = 0, y = 0, z = 0, up = 0, down = 0;
};

/// Runs tests/tools/three_import.mjs; nullopt when three.js is not installed (scripts/setup).
std::optional<Loaded> load_in_three(const fs::path& glb) {
    const fs::path modules = fs::path(CRACKLE_SOURCE_DIR) / ".tools" / "node_modules";
    if (!fs::exists(modules / "three" / "package.json")) {
        const char* require = std::getenv("CRACKLE_REQUIRE_VALIDATOR");
        REQUIRE_MESSAGE(!(require && std::string(require) == "1"), "three.js missing: run scripts/setup");
        return std::nullopt;
    }
    const std::string cmd = "node '" + (fs::path(CRACKLE_SOURCE_DIR) / "tests/tools/three_import.mjs").string() + "' '"
                            + modules.string() + "' '" + glb.string() + "' 2>&1";
    std::string out;
    FILE* pipe = popen(cmd.c_str(), "r");
    char buf[4096];
    while (pipe && fgets(buf, sizeof buf, pipe))
        out += buf;
    if (pipe) pclose(pipe);
    std::smatch m;
    const std::regex line(R"(size x ([0-9.]+) y ([0-9.]+) z ([0-9.]+) m; area facing \+Y ([0-9.]+) m2, -Y ([0-9.]+))");
    REQUIRE_MESSAGE(std::regex_search(out, m, line), out);
    return Loaded{std::stod(m[1]), std::stod(m[2]), std::stod(m[3]), std::stod(m[4]), std::stod(m[5])};
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("export: three.js loads the mud tile flat and face up and the bark trunk standing along +Y") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("engine-import");
        for (const char* preset : {"mud", "bark"}) {
            CAPTURE(preset);
            const fs::path glb = dir / (std::string(preset) + ".glb");
            const auto r = test::run_cli({"-q", "export", preset, "--format", "glb", "--size", "32", "--set",
                                          "simulation.elements=600", "--out", glb.string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);
            const auto loaded = load_in_three(glb);
            if (!loaded) return;
            if (std::string(preset) == "mud") {
                // A 0.5 m tile, a few millimetres thick, its plates facing up.
                CHECK(loaded->x > 0.4);
                CHECK(loaded->z > 0.4);
                CHECK(loaded->y < 0.05);
                CHECK(loaded->up > 0.5 * loaded->x * loaded->z);
                CHECK(loaded->down < 0.01 * loaded->up);
            } else {
                // The trunk: 0.5 m tall along Y, round in X and Z.
                CHECK(loaded->y > 0.45);
                CHECK(loaded->x < 0.5 * loaded->y);
                CHECK(loaded->z < 0.5 * loaded->y);
            }
        }
    }
}
