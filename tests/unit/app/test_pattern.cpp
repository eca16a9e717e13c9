// Crack-pattern files and the pattern cache (issue 14): a bake from a saved pattern is the bake
// straight after the simulation, byte for byte, on all three surfaces; damaged files are refused;
// the cache serves a pattern only for the same simulation keys, seed and build.
#include "app/run/pattern_store.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "fracture/pattern_file.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <cstring>
#include <map>
#include <optional>

using namespace crackle;
using test::run_cli;
namespace fs = std::filesystem;

namespace {

/// Sets an environment variable for one scope.
class EnvGuard {
public:
    EnvGuard(const char* name, const std::string& value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        setenv(name, value.c_str(), 1);
    }
    ~EnvGuard() {
        if (m_old)
            setenv(m_name, m_old->c_str(), 1);
        else
            unsetenv(m_name);
    }

private:
    const char* m_name;
    std::optional<std::string> m_old;
};

/// Every file of a folder, name → bytes.
std::map<std::string, std::string> files_of(const fs::path& dir) {
    std::map<std::string, std::string> files;
    for (const auto& e : fs::directory_iterator(dir))
        files[e.path().filename().string()] = read_file(e.path());
    return files;
}

Json report_of(const fs::path& path) {
    return Json::parse(read_file(path), path.string());
}

std::string source_of(const fs::path& report) {
    const Json j = report_of(report);
    const Json* s = j.find("pattern_source");
    return s ? s->as_string() : "";
}

struct SmallScene {
    const char* preset;
    const char* elements;
};
// Plane, cylinder and sphere: the plane is the easy case.
const SmallScene SCENES[] = {
    {"mud", "simulation.elements=500"}, {"bark", "simulation.elements=700"}, {"fruit", "simulation.elements=900"}};

} // namespace

TEST_SUITE("app") {
    TEST_CASE("pattern file: a bake from a saved pattern is byte-identical to a direct bake on plane, cylinder and "
              "sphere") {
        if (!test::gl_context_or_skip()) return;
        for (const SmallScene& scene : SCENES) {
            CAPTURE(scene.preset);
            const fs::path dir = test::scratch_dir(std::string("pattern-") + scene.preset);
            const fs::path pattern = dir / "p.crackle";
            auto r = run_cli({"-q", "simulate", scene.preset, "--set", scene.elements, "--save", pattern.string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);

            // The file reads back bit for bit.
            const std::string bytes = read_file(pattern);
            const fracture::PatternFile file = fracture::decode_pattern(bytes, pattern.string());
            const std::vector<std::uint8_t> again = fracture::encode_pattern(file.pattern, file.header);
            CHECK(std::string(again.begin(), again.end()) == bytes);
            CHECK(file.pattern.num_fragments > 1);
            CHECK(file.header.find("simulation_key") != nullptr);

            // Bake straight from a simulation and from the file: the same bytes in every map.
            r = run_cli({"-q", "bake", scene.preset, "--set", scene.elements, "--size", "64", "--no-cache", "--out",
                         (dir / "direct").string(), "--json", (dir / "direct.json").string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);
            r = run_cli({"-q", "bake", scene.preset, "--set", scene.elements, "--size", "64", "--pattern",
                         pattern.string(), "--out", (dir / "loaded").string(), "--json",
                         (dir / "loaded.json").string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);
            const auto direct = files_of(dir / "direct"), loaded = files_of(dir / "loaded");
            REQUIRE(direct.size() == 8);
            REQUIRE(loaded.size() == direct.size());
            for (const auto& [name, content] : direct) {
                CAPTURE(name);
                CHECK(loaded.at(name) == content);
            }
            CHECK(source_of(dir / "direct.json") == "simulated");
            CHECK(source_of(dir / "loaded.json") == "file");
            // The report's statistics come out the same whichever way the pattern arrived.
            for (const char* key : {"fragments", "fracture_events", "crack_length_per_area", "elements_final"})
                CHECK(report_of(dir / "direct.json").find(key)->as_number()
                      == report_of(dir / "loaded.json").find(key)->as_number());
        }
    }

    TEST_CASE("pattern file: truncated, corrupt, foreign and other-version files are refused with exit code 2") {
        const fs::path dir = test::scratch_dir("pattern-damaged");
        const fs::path pattern = dir / "p.crackle";
        auto r = run_cli({"-q", "simulate", "mud", "--set", "simulation.elements=400", "--save", pattern.string()});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        const std::string good = read_file(pattern);
        CHECK_NOTHROW(fracture::decode_pattern(good, "good"));

        auto refused = [](const std::string& bytes) {
            try {
                fracture::decode_pattern(bytes, "damaged");
            } catch (const InputError& e) {
                return std::strstr(e.what(), "damaged") != nullptr;
            }
            return false;
        };
        for (int k = 0; k < 16; ++k) {
            CAPTURE(k);
            CHECK(refused(good.substr(0, good.size() * static_cast<std::size_t>(k) / 16)));
            std::string flipped = good;
            flipped[40 + (good.size() - 48) * static_cast<std::size_t>(k) / 16] ^= 0x20;
            CHECK(refused(flipped));
        }
        CHECK(refused("P6\n1 1\n255\n\x01\x02\x03"));
        std::string other_version = good;
        other_version[16] = 99; // the u32 after the 16-byte signature
        CHECK(refused(other_version));

        // Through the CLI: exit 2, the file named, nothing written.
        write_file_atomically(dir / "bad.crackle", good.substr(0, good.size() / 2));
        r = run_cli({"bake", "mud", "--pattern", (dir / "bad.crackle").string(), "--size", "32", "--out",
                     (dir / "out").string()});
        CHECK(r.code == 2);
        CHECK(r.err.find("bad.crackle") != std::string::npos);
        CHECK(!fs::exists(dir / "out"));
        r = run_cli({"bake", "mud", "--pattern", (dir / "missing.crackle").string(), "--out", (dir / "out").string()});
        CHECK(r.code == 2);
    }

    TEST_CASE("pattern cache: reused when only bake or post keys change, simulated again when a simulation key, the "
              "seed or the build changes") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("pattern-cache");
        const EnvGuard cache("CRACKLE_CACHE", (dir / "cache").string());
        int n = 0;
        auto bake = [&](std::vector<std::string> extra) {
            std::vector<std::string> args = {"-q",
                                             "bake",
                                             "mud",
                                             "--set",
                                             "simulation.elements=400",
                                             "--size",
                                             "32",
                                             "--out",
                                             (dir / "out").string()};
            args.insert(args.end(), extra.begin(), extra.end());
            const fs::path report = dir / ("r" + std::to_string(n++) + ".json");
            args.push_back("--json");
            args.push_back(report.string());
            const auto r = run_cli(args);
            REQUIRE_MESSAGE(r.code == 0, r.err);
            return source_of(report);
        };
        CHECK(bake({}) == "simulated");
        CHECK(bake({}) == "cache");
        CHECK(bake({"--set", "bake.color=[0.2,0.3,0.4]"}) == "cache");
        CHECK(bake({"--set", "post.bevel=0.001", "--set", "bake.size=48"}) == "cache");
        CHECK(bake({"--set", "material.thickness=[0.011,0.011]"}) == "simulated");
        CHECK(bake({"--seed", "7"}) == "simulated");
        CHECK(bake({"--seed", "7"}) == "cache");
        CHECK(bake({"--no-cache"}) == "simulated");

        // A cached pattern from another build of crackle is never served, even under the same key.
        std::size_t files = 0;
        for (const auto& e : fs::directory_iterator(dir / "cache")) {
            ++files;
            fracture::PatternFile f = fracture::decode_pattern(read_file(e.path()), e.path().string());
            f.header["build"] = "0.0.0-someotherbuild";
            const auto bytes = fracture::encode_pattern(f.pattern, f.header);
            write_file_atomically(e.path(),
                                  std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
        }
        CHECK(files == 3); // the default seed, thickness 0.011, seed 7
        CHECK(bake({}) == "simulated");
        // A damaged cache file is simulated over, not an error.
        for (const auto& e : fs::directory_iterator(dir / "cache"))
            write_file_atomically(e.path(), "CRACKLE-PATTERN\ngarbage");
        CHECK(bake({}) == "simulated");
        CHECK(bake({}) == "cache");
    }

    TEST_CASE("pattern cache: the key follows the element count auto resolves from bake.size, and nothing from "
              "[bake] or [post] otherwise") {
        const fs::path dir = test::scratch_dir("pattern-key");
        auto key = [](std::vector<std::string> overrides) {
            io::PresetRequest request;
            request.name_or_path = "mud";
            request.overrides = std::move(overrides);
            const io::Preset preset = io::load_preset(request);
            return app::simulation_key(preset, app::make_run_plan(preset));
        };
        const std::string base = key({"simulation.elements=\"auto\"", "bake.size=64"});
        CHECK(key({"simulation.elements=\"auto\"", "bake.size=64", "bake.color=[0.1,0.1,0.1]", "post.curl=1.0"})
              == base);
        CHECK(key({"simulation.elements=\"auto\"", "bake.size=4096"}) != base);
        CHECK(key({"simulation.elements=\"auto\"", "bake.size=64", "material.young_modulus=2.0e6"}) != base);
        CHECK(base.find("bake.") == std::string::npos);
        CHECK(base.find("post.") == std::string::npos);
        CHECK(base.find("simulation.seed") != std::string::npos);
    }
}
