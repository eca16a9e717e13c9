#include "core/atomic_file.hpp"
#include "core/json.hpp"
#include "io/png.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <regex>
#include <set>

using namespace crackle;
using test::contains;
using test::run_cli;
namespace fs = std::filesystem;

namespace {

/// A top-level number of a JSON report (NaN if absent).
double number_field(const std::string& json, const std::string& key) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + key + "\": (-?[0-9.eE+-]+)"))) return std::nan("");
    return std::stod(m[1].str());
}
} // namespace

TEST_SUITE("app") {
    TEST_CASE("cli: --help and --version and a missing subcommand") {
        const auto help = run_cli({"--help"});
        CHECK(help.code == 0);
        CHECK(contains(help.out, "presets"));
        CHECK(contains(help.out, "mesh"));
        const auto version = run_cli({"--version"});
        CHECK(version.code == 0);
        CHECK(contains(version.out, "crackle 0."));
        const auto none = run_cli({});
        CHECK(none.code == 2);
        CHECK(contains(none.err, "error:"));
        const auto unknown = run_cli({"frobnicate"});
        CHECK(unknown.code == 2);
    }

    TEST_CASE("cli: bench has explicit subcommands (study, speedup, scale, micro) and still takes the older forms") {
        const auto help = run_cli({"bench", "--help"});
        CHECK(help.code == 0);
        for (const char* sub : {"study", "speedup", "scale", "micro"})
            CHECK(contains(help.out, sub));
        // Names are checked before anything runs, in the new form and the old alike.
        for (const std::vector<std::string>& args :
             {std::vector<std::string>{"bench", "micro", "nothing"}, std::vector<std::string>{"bench", "nothing"}}) {
            const auto r = run_cli(args);
            CHECK(r.code == 2);
            CHECK(contains(r.err, "unknown scene 'nothing'"));
            CHECK(contains(r.err, "solve, local"));
        }
        for (const std::vector<std::string>& args : {std::vector<std::string>{"bench", "study", "--methods", "nope"},
                                                     std::vector<std::string>{"bench", "--methods", "nope"}}) {
            const auto r = run_cli(args);
            CHECK(r.code == 2);
            CHECK(contains(r.err, "unknown method 'nope'"));
            CHECK(contains(r.err, "fem-split-tip")); // the list comes from the method registry
        }
        CHECK(contains(run_cli({"bench", "speedup", "--baseline", "/no/such/crackle"}).err, "not an executable"));
        // A micro-benchmark runs the same by either name.
        const auto micro = run_cli({"-q", "bench", "micro", "solve", "--quick"});
        const auto old = run_cli({"-q", "bench", "solve", "--quick"});
        CHECK(micro.code == 0);
        CHECK(old.code == 0);
        CHECK(contains(micro.out, "| 2000 |"));
        CHECK(contains(old.out, "| 2000 |"));
    }

    TEST_CASE("cli: global flags are taken before or after the subcommand") {
        // -q after the subcommand silences the summary exactly as before it does.
        const auto before = run_cli({"-q", "mesh", "mud", "--set", "simulation.elements=300"});
        const auto after = run_cli({"mesh", "mud", "--set", "simulation.elements=300", "-q"});
        const auto loud = run_cli({"mesh", "mud", "--set", "simulation.elements=300"});
        REQUIRE(before.code == 0);
        REQUIRE(after.code == 0);
        REQUIRE(loud.code == 0);
        CHECK(before.out.empty());
        CHECK(after.out.empty());
        CHECK_FALSE(loud.out.empty());
        // Nested subcommands too; and an unknown option is still refused with exit code 2.
        CHECK(run_cli({"presets", "list", "-v"}).code == 0);
        CHECK(run_cli({"mesh", "mud", "--no-such-flag"}).code == 2);
    }

    TEST_CASE("cli: presets list and show and doc") {
        const auto list = run_cli({"presets", "list"});
        CHECK(list.code == 0);
        CHECK(contains(list.out, "bark"));
        CHECK(contains(list.out, "mud/thickness-gradient"));
        const auto show = run_cli({"presets", "show", "mud", "--seed", "9"});
        CHECK(show.code == 0);
        CHECK(contains(show.out, "[surface]"));
        CHECK(contains(show.out, "kind = \"plane\""));
        CHECK(contains(show.out, "seed = 9"));
        CHECK(contains(show.out, "jitter = 0.25")); // defaults included
        const auto doc = run_cli({"presets", "doc"});
        CHECK(doc.code == 0);
        CHECK(contains(doc.out, "| `young_modulus` |"));
    }

    TEST_CASE("cli: bad input exits with code 2 and 'error: <file>:<line>: <what> (<how to fix>)' and writes nothing") {
        const auto dir = test::scratch_dir("cli-bad");
        const auto preset = test::write_text(dir / "p.toml", "extends = \"mud\"\n[material]\npoisson_ratio = 0.7\n");
        const auto r = run_cli(
            {"mesh", preset.string(), "--obj", (dir / "out.obj").string(), "--json", (dir / "out.json").string()});
        CHECK(r.code == 2);
        const std::regex format(R"(^error: .*p\.toml:3: .+ \(.+\)\n$)");
        CHECK_MESSAGE(std::regex_match(r.err, format), r.err);
        CHECK_FALSE(fs::exists(dir / "out.obj"));
        CHECK_FALSE(fs::exists(dir / "out.json"));
        CHECK(r.out.empty());

        const auto missing = run_cli({"mesh", (dir / "missing.toml").string()});
        CHECK(missing.code == 2);
        CHECK(contains(missing.err, "not found"));
        const auto set = run_cli({"mesh", "mud", "--set", "simulation.elements=5000000"});
        CHECK(set.code == 2);
        CHECK(contains(set.err, "--set simulation.elements=5000000"));
        const auto seed = run_cli({"mesh", "mud", "--seed", "-4"});
        CHECK(seed.code == 2);
        // A seed that is not a whole number in range is named in words, not as a 309-digit double.
        for (const char* bad : {"1..10", "abc", "9000000000000000001"}) {
            const auto r_seed = run_cli({"mesh", "mud", "--seed", bad});
            CAPTURE(r_seed.err);
            CHECK(r_seed.code == 2);
            CHECK(contains(r_seed.err, "--seed"));
            CHECK(contains(r_seed.err, "whole number"));
            CHECK(r_seed.err.size() < 200);
        }
    }

    TEST_CASE("cli: mesh works on all three surfaces and reports its figures as JSON") {
        const auto dir = test::scratch_dir("cli-mesh");
        for (const char* preset : {"bark", "mud", "fruit"}) {
            CAPTURE(preset);
            const fs::path json = dir / (std::string(preset) + ".json");
            const auto r = run_cli({"mesh", preset, "--set", "simulation.elements=600", "--json", json.string()});
            REQUIRE(r.code == 0);
            CHECK(contains(r.out, "min angle"));
            const std::string report = test::slurp(json);
            for (const char* field : {"\"nodes\"", "\"faces\"", "\"min_angle_deg\"", "\"mean_min_angle_deg\"",
                                      "\"fraction_min_angle_below_10deg\"", "\"edge_length_m\"", "\"wall_seconds\"",
                                      "\"sampling\"", "\"triangulation\"", "\"peak_memory_mb\"", "\"seed\": 1"})
                CHECK_MESSAGE(contains(report, field), field);
        }
        const auto quiet = run_cli({"-q", "mesh", "mud", "--set", "simulation.elements=200"});
        CHECK(quiet.code == 0);
        CHECK(quiet.out.empty());
    }

    TEST_CASE("cli: the same preset and seed give bit-identical mesh output but another seed does not") {
        const auto dir = test::scratch_dir("cli-determinism");
        auto mesh_obj = [&](const std::string& preset, const std::string& seed, const std::string& name) {
            const fs::path obj = dir / name;
            const auto r = run_cli(
                {"-q", "mesh", preset, "--seed", seed, "--set", "simulation.elements=1500", "--obj", obj.string()});
            REQUIRE(r.code == 0);
            return test::slurp(obj);
        };
        for (const char* preset : {"mud", "fruit", "bark"}) {
            CAPTURE(preset);
            const std::string a = mesh_obj(preset, "5", "a.obj");
            const std::string b = mesh_obj(preset, "5", "b.obj");
            const std::string c = mesh_obj(preset, "6", "c.obj");
            CHECK(a.size() > 1000);
            CHECK(a == b);
            CHECK(a != c);
        }
    }

    TEST_CASE("cli: every built-in preset meshes at tiny resolution") {
        const auto list = run_cli({"presets", "list"});
        std::istringstream is(list.out);
        std::string line;
        int count = 0;
        while (std::getline(is, line)) {
            const std::string name = line.substr(0, line.find(' '));
            CAPTURE(name);
            const auto r = run_cli({"-q", "mesh", name, "--set", "simulation.elements=300"});
            CHECK(r.code == 0);
            CHECK(r.err.empty());
            ++count;
        }
        CHECK(count >= 4);
    }

    TEST_CASE("cli: a grayscale PNG next to the preset drives the layer thickness (§5.9)") {
        const auto dir = test::scratch_dir("cli-image");
        // A horizontal ramp: black at the left (u = 0), white at the right.
        GrayImage img;
        img.width = 32;
        img.height = 8;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                img.pixels.push_back(static_cast<float>(x / 31.0));
        const auto png = io::encode_png_gray(img, 8);
        write_file_atomically(dir / "maps" / "ramp.png",
                              std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
        const auto preset = test::write_text(dir / "p.toml", "extends = \"mud\"\n"
                                                             "[variation.thickness]\n"
                                                             "pattern = \"image\"\n"
                                                             "amplitude = 0.5\n"
                                                             "image = \"maps/ramp.png\"\n");
        const auto r = run_cli(
            {"mesh", preset.string(), "--set", "simulation.elements=800", "--json", (dir / "report.json").string()});
        REQUIRE(r.code == 0);
        // Thickness 1 cm · (1 ± 0.5): close to 0.5 cm on the dark side and 1.5 cm on the bright side.
        const std::string report = test::slurp(dir / "report.json");
        const auto thickness_min = std::stod(report.substr(report.find("\"min\"", report.find("thickness_m")) + 7));
        const auto thickness_max = std::stod(report.substr(report.find("\"max\"", report.find("thickness_m")) + 7));
        CHECK(thickness_min < 0.0065);
        CHECK(thickness_min > 0.0049);
        CHECK(thickness_max > 0.0135);
        CHECK(thickness_max < 0.0151);
    }

    TEST_CASE("cli: simulate runs fem-split (the default) and fem-remove on plane and cylinder and sphere and writes "
              "its report") {
        const auto dir = test::scratch_dir("cli-simulate");
        for (const char* preset : {"mud", "bark", "fruit"})
            for (const std::string method : {"fem-split", "fem-remove"}) {
                CAPTURE(preset);
                CAPTURE(method);
                const std::string stem = std::string(preset) + "-" + method;
                const fs::path json = dir / (stem + ".json");
                const fs::path csv = dir / (stem + ".csv");
                const fs::path png = dir / (stem + ".png");
                std::vector<std::string> args{"simulate", preset,        "--set",      "simulation.elements=400",
                                              "--json",   json.string(), "--events",   csv.string(),
                                              "--png",    png.string(),  "--png-size", "64"};
                if (method != "fem-split") args.insert(args.end(), {"--set", "simulation.method=" + method});
                const auto r = run_cli(args);
                REQUIRE(r.code == 0);
                CHECK(contains(r.out, "fragments"));
                const std::string report = test::slurp(json);
                CHECK(contains(report, "\"method\": \"" + method + "\""));
                if (method == "fem-split") {
                    CHECK(number_field(report, "splits") > 0);
                    CHECK(number_field(report, "tip_extensions") > 0);
                }
                // The field names fixed in design.md.
                for (const char* field :
                     {"\"seed\"", "\"elements_initial\"", "\"elements_final\"", "\"nodes\"", "\"fracture_events\"",
                      "\"fragments\"", "\"mean_fragment_area\"", "\"crack_length_per_area\"", "\"anisotropy\"",
                      "\"dominant_angle_deg\"", "\"psi6\"", "\"t_junction_fraction\"", "\"y_junction_fraction\"",
                      "\"min_angle_deg\"", "\"wall_seconds\"", "\"peak_memory_mb\""})
                    CHECK_MESSAGE(contains(report, field), field);
                const std::string events = test::slurp(csv);
                CHECK(events.rfind("time,x,y,z,u,v,kind,ratio\n", 0) == 0);
                CHECK(std::count(events.begin(), events.end(), '\n') > 5);
                CHECK(test::slurp(png).substr(1, 3) == "PNG");
            }
    }

    TEST_CASE("cli: simulate and bake run mass-spring on plane and cylinder and sphere") {
        const bool gl = test::gl_context_or_skip() != nullptr;
        const auto dir = test::scratch_dir("cli-mass-spring");
        for (const char* preset : {"mud", "bark", "fruit"}) {
            for (const char* lattice : {"random", "regular"}) {
                CAPTURE(preset);
                CAPTURE(lattice);
                const fs::path json = dir / (std::string(preset) + lattice + ".json");
                const auto r = run_cli({"-q", "simulate", preset, "--set", "simulation.method=mass-spring", "--set",
                                        std::string("simulation.lattice=") + lattice, "--set", "simulation.layers=2",
                                        "--set", "simulation.elements=600", "--json", json.string()});
                REQUIRE_MESSAGE(r.code == 0, r.err);
                const std::string report = test::slurp(json);
                CHECK(contains(report, "\"method\": \"mass-spring\""));
                CHECK(number_field(report, "breaks") > 0);
                CHECK(number_field(report, "crack_length_per_area") > 0.0);
                CHECK(std::regex_search(report, std::regex("\"crack_depth_histogram\": \\{\\s*\"[12]\": [1-9]")));
            }
            if (!gl) continue;
            const auto b = run_cli({"-q", "bake", preset, "--size", "64", "--set", "simulation.method=mass-spring",
                                    "--set", "simulation.elements=600", "--out", (dir / preset).string()});
            CHECK_MESSAGE(b.code == 0, b.err);
            CHECK(fs::exists(dir / preset / (std::string(preset) + "_Displacement.png")));
        }
    }

    TEST_CASE("cli: a mass-spring relaxation that cannot converge exits with code 3 and reports its numbers") {
        const auto r = run_cli({"simulate", "mud", "--set", "simulation.method=mass-spring", "--set",
                                "simulation.elements=300", "--set", "simulation.newton_iterations=1"});
        CHECK(r.code == 3);
        CHECK(contains(r.err, "Newton iterations"));
        CHECK(contains(r.err, "largest force"));
    }

    TEST_CASE("cli: a solver that cannot converge exits with code 3 and reports iterations and residual") {
        const auto r = run_cli(
            {"simulate", "mud", "--set", "simulation.elements=300", "--set", "simulation.solver_max_iterations=1"});
        CHECK(r.code == 3);
        CHECK(contains(r.err, "iterations"));
        CHECK(contains(r.err, "residual"));
    }

    TEST_CASE("cli: a curved surface meshed too coarsely to hold its wedges is refused with the elements it needs") {
        // Stability envelope (issue 12): with fewer than about six triangles around, a wedge
        // spans more than 60° and turns inside out; these asserted (exit 1) before.
        const auto tall = run_cli({"simulate", "bark", "--set", "simulation.method=fem-remove", "--set",
                                   "simulation.elements=1500", "--set", "surface.size=[0.5,50]"});
        CHECK(tall.code == 2);
        CHECK(contains(tall.err, "simulation.elements"));
        CHECK(contains(tall.err, "at least 8314"));
        const auto narrow = run_cli({"simulate", "bark", "--set", "simulation.method=graph-fem", "--set",
                                     "simulation.elements=800", "--set", "surface.size=[0.05,5]"});
        CHECK(narrow.code == 2);
        const auto ball =
            run_cli({"simulate", "fruit", "--set", "simulation.elements=32", "--set", "surface.size=[1]"});
        CHECK(ball.code == 0); // a sphere needs only about 27 triangles
        // At the limit the layer builds and cracks, whatever the seed.
        for (const char* seed : {"1", "2", "3"}) {
            CAPTURE(seed);
            const auto r = run_cli({"-q", "simulate", "bark", "--seed", seed, "--set", "simulation.method=fem-remove",
                                    "--set", "simulation.elements=84", "--set", "simulation.max_events=20"});
            CHECK_MESSAGE(r.code == 0, r.err);
        }
    }

    TEST_CASE("cli: a misspelt fracture method is refused before any work, naming the methods") {
        const auto r = run_cli({"simulate", "mud", "--set", "simulation.method=graph-fm"});
        CHECK(r.code == 2);
        CHECK(contains(r.err, "simulation.method"));
        CHECK(contains(r.err, "graph-fem"));
    }

    TEST_CASE("cli: graph-fem runs from every preset with --set, reports a system that never changed size, and "
              "bakes and exports its pattern") {
        const bool gl = test::gl_context_or_skip() != nullptr;
        const auto dir = test::scratch_dir("cli-graph-fem");
        for (const char* preset : {"mud", "bark", "fruit", "mud/thickness-gradient"}) {
            CAPTURE(preset);
            std::string name = preset;
            std::replace(name.begin(), name.end(), '/', '_');
            const fs::path json = dir / (name + ".json");
            const auto r = run_cli({"-q", "simulate", preset, "--set", "simulation.method=graph-fem", "--set",
                                    "simulation.elements=600", "--json", json.string()});
            REQUIRE(r.code == 0);
            const std::string report = test::slurp(json);
            CHECK(contains(report, "\"method\": \"graph-fem\""));
            CHECK(number_field(report, "breaks") > 0);
            CHECK(number_field(report, "nonzeros_final") == number_field(report, "nonzeros_initial"));
            CHECK(number_field(report, "graph_edges") > 0);
        }
        if (gl) {
            const auto b = run_cli({"-q", "bake", "mud", "--size", "64", "--set", "simulation.method=graph-fem",
                                    "--set", "simulation.elements=600", "--out", (dir / "bake").string()});
            CHECK_MESSAGE(b.code == 0, b.err);
            CHECK(fs::exists(dir / "bake" / "mud_Displacement.png"));
            const auto e = run_cli({"-q", "export", "bark", "--format", "glb", "--set", "simulation.method=graph-fem",
                                    "--set", "simulation.elements=600", "--out", (dir / "bark.glb").string()});
            CHECK_MESSAGE(e.code == 0, e.err);
            CHECK(fs::file_size(dir / "bark.glb") > 1000);
        }
        // An averaging radius of a tile's size would take hours: refused before any work.
        const auto big = run_cli({"-q", "simulate", "mud", "--set", "simulation.method=graph-fem", "--set",
                                  "simulation.damage_radius=1", "--json", (dir / "big.json").string()});
        CHECK(big.code == 2);
        CHECK(contains(big.err, "simulation.damage_radius"));
        CHECK(contains(big.err, "use at most"));
        CHECK_FALSE(fs::exists(dir / "big.json"));
        // A solver that cannot converge is a numeric failure: exit 3, nothing written.
        const fs::path json = dir / "failed.json";
        const auto r = run_cli({"-q", "simulate", "mud", "--set", "simulation.method=graph-fem", "--set",
                                "simulation.elements=300", "--set", "simulation.solver_max_iterations=1", "--json",
                                json.string()});
        CHECK(r.code == 3);
        CHECK(contains(r.err, "residual"));
        CHECK_FALSE(fs::exists(json));
    }

    TEST_CASE("cli: simulate is deterministic for a preset and seed") {
        const auto dir = test::scratch_dir("cli-simulate-determinism");
        auto events = [&](const std::string& seed, const std::string& name) {
            const fs::path csv = dir / name;
            REQUIRE(run_cli({"-q", "simulate", "mud", "--seed", seed, "--set", "simulation.elements=500", "--events",
                             csv.string()})
                        .code
                    == 0);
            return test::slurp(csv);
        };
        const std::string a = events("3", "a.csv"), b = events("3", "b.csv"), c = events("4", "c.csv");
        CHECK(a == b);
        CHECK(a != c);
    }

    TEST_CASE("cli: bake writes the ambientCG-named texture set and a report") {
        if (!test::gl_context_or_skip()) return;
        const auto dir = test::scratch_dir("cli-bake");
        const auto r =
            run_cli({"-q", "bake", "mud", "--size", "64", "--set", "simulation.elements=500", "--set", "bake.exr=true",
                     "--out", (dir / "maps").string(), "--json", (dir / "r.json").string()});
        REQUIRE_MESSAGE(r.code == 0, r.err);
        for (const char* suffix : {"Color.png", "NormalGL.png", "NormalDX.png", "Displacement.png",
                                   "AmbientOcclusion.png", "Roughness.png", "Mask.png", "ID.png", "Displacement.exr"})
            CHECK_MESSAGE(fs::exists(dir / "maps" / (std::string("mud_") + suffix)), suffix);
        const std::string report = test::slurp(dir / "r.json");
        CHECK(contains(report, "\"displacement_scale_m\""));
        CHECK(contains(report, "\"bake.render\""));
        // No temporary files left behind.
        for (const auto& e : fs::directory_iterator(dir / "maps"))
            CHECK(e.path().string().find(".tmp") == std::string::npos);
    }

    TEST_CASE("cli: bake and export refuse bad output requests with exit code 2 and leave nothing behind") {
        const auto dir = test::scratch_dir("cli-bake-bad");
        CHECK(run_cli({"bake", "mud", "--size", "0"}).code == 2);
        CHECK(run_cli({"bake", "mud", "--size", "20000"}).code == 2);
        CHECK(run_cli({"bake", "mud", "--set", "bake.size=100000"}).code == 2);
        CHECK(run_cli({"export", "mud", "--format", "fbx"}).code == 2);
        if (!test::gl_context_or_skip()) return;
        // A folder that cannot be created: everything is computed, nothing is written.
        const auto r = run_cli({"-q", "bake", "mud", "--size", "32", "--set", "simulation.elements=300", "--out",
                                "/proc/crackle-no-such-dir/maps"});
        CHECK(r.code == 2);
        CHECK(contains(r.err, "/proc/crackle-no-such-dir"));
        CHECK_FALSE(fs::exists("/proc/crackle-no-such-dir"));
    }

    TEST_CASE("cli: --size N is the longer side with square texels, --size WxH is exact, bad sizes exit 2") {
        CHECK(run_cli({"bake", "mud", "--size", "10x64"}).code == 2);
        CHECK(run_cli({"bake", "mud", "--size", "64x"}).code == 2);
        CHECK(run_cli({"bake", "mud", "--size", "64x32x2"}).code == 2);
        CHECK(contains(run_cli({"bake", "mud", "--size", "64y32"}).err, "--size"));
        if (!test::gl_context_or_skip()) return;
        const auto dir = test::scratch_dir("cli-bake-size");
        auto dimensions = [&](const std::vector<std::string>& extra) {
            std::vector<std::string> args = {
                "-q",    "bake",      "mud", "--set", "simulation.elements=300", "--set", "simulation.tip_submodel=0",
                "--out", dir.string()};
            args.insert(args.end(), extra.begin(), extra.end());
            const auto r = run_cli(args);
            REQUIRE_MESSAGE(r.code == 0, r.err);
            const std::string bytes = test::slurp(dir / "mud_Color.png");
            int w = 0, h = 0;
            io::decode_png_rgb8(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), w, h);
            return std::make_pair(w, h);
        };
        CHECK(dimensions({"--size", "64"}) == std::make_pair(64, 64));
        CHECK(dimensions({"--size", "96x48"}) == std::make_pair(96, 48));
        // A plane twice as wide as tall: square texels by default.
        CHECK(dimensions({"--size", "64", "--set", "surface.size=[0.4,0.2]"}) == std::make_pair(64, 32));
        CHECK(dimensions({"--size", "64", "--set", "surface.size=[0.2,0.4]"}) == std::make_pair(32, 64));
    }

    TEST_CASE("cli: export writes OBJ and glTF and GLB with only the maps they reference") {
        if (!test::gl_context_or_skip()) return;
        const auto dir = test::scratch_dir("cli-export");
        const std::map<std::string, std::set<std::string>> expected = {
            {"glb", {"tile.glb"}},
            {"gltf", {"tile.gltf", "tile.bin", "tile_Color.png", "tile_NormalGL.png", "tile_ORM.png"}},
            {"obj", {"tile.obj", "tile.mtl", "tile_Color.png", "tile_NormalGL.png", "tile_Roughness.png"}}};
        for (const auto& [format, names] : expected) {
            CAPTURE(format);
            const fs::path file = dir / format / ("tile." + format);
            const auto r =
                run_cli({"-q", "export", "mud", "--format", format, "--size", "32", "--set", "simulation.elements=300",
                         "--out", file.string(), "--json", (dir / (format + ".json")).string()});
            REQUIRE_MESSAGE(r.code == 0, r.err);
            CHECK(fs::file_size(file) > 1000);
            std::set<std::string> found;
            for (const auto& e : fs::directory_iterator(dir / format))
                found.insert(e.path().filename().string());
            CHECK(found == names);
            CHECK(number_field(test::slurp(dir / (format + ".json")), "displacement_scale_m") > 0);
        }
    }
}
