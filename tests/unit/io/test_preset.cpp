#include "core/error.hpp"
#include "io/preset.hpp"
#include "support/cli_runner.hpp"
#include "support/presets.hpp"

#include <doctest/doctest.h>

#include <fstream>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

using test::load;
using test::load_error;

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

} // namespace

TEST_SUITE("io") {
    TEST_CASE("preset: every built-in preset loads and defaults fill every schema key") {
        const auto names = io::builtin_preset_names();
        CHECK(names.size() >= 4);
        for (const auto& name : names) {
            CAPTURE(name);
            const io::Preset p = load(name);
            for (const io::KeySpec& k : io::preset_schema())
                CHECK_NOTHROW(p.entry(k.name()));
            CHECK_FALSE(io::builtin_preset_summary(name).empty());
        }
        const io::Preset bark = load("bark");
        CHECK(bark.text("surface.kind") == "cylinder");
        CHECK(bark.entry("simulation.jitter").source.file.empty()); // not set: the default
        CHECK(bark.number("simulation.jitter") == 0.25);
    }

    TEST_CASE("preset: extends inherits and the child overrides and sources are tracked") {
        const auto dir = test::scratch_dir("preset-extends");
        test::write_text(dir / "base.toml", "extends = \"mud\"\n[material]\nthreshold_stress = 3.0e4\n");
        test::write_text(dir / "child.toml", "extends = \"base\"\n[material]\ntoughness = 75\n");
        const io::Preset p = load((dir / "child.toml").string());
        CHECK(p.number("material.toughness") == 75.0);         // child (an integer, read as a float)
        CHECK(p.number("material.threshold_stress") == 3.0e4); // parent, a file beside it
        CHECK(p.text("surface.kind") == "plane");              // grandparent, the built-in mud
        CHECK(contains(p.entry("material.toughness").source.text(), "child.toml:3"));
        CHECK(contains(p.entry("surface.kind").source.text(), "builtin:mud.toml"));
    }

    TEST_CASE("preset: --set overrides with type checking") {
        const io::Preset p =
            load("bark", {"material.thickness=[0.02, 0.03]", "surface.kind=plane", "simulation.elements=500"});
        CHECK(p.numbers("material.thickness") == std::vector<double>{0.02, 0.03});
        CHECK(p.text("surface.kind") == "plane");
        CHECK(p.integer("simulation.elements") == 500);
        CHECK(p.entry("simulation.elements").source.text() == "--set");
        CHECK(contains(load_error("bark", {"material.young_modulus=stiff"}), "not a valid value"));
        CHECK(contains(load_error("bark", {"material.youngs_modulus=1"}), "did you mean 'material.young_modulus'"));
        CHECK(contains(load_error("bark", {"material.poisson_ratio"}), "expected section.key=value"));
        CHECK(contains(load_error("bark", {"surface.kind=cilinder"}), "did you mean 'cylinder'"));
    }

    TEST_CASE("preset: each kind of bad input is an InputError naming file and line and a fix") {
        const auto dir = test::scratch_dir("preset-bad");
        struct Case {
            const char* what;
            std::string toml;
            std::vector<std::string> expected;
        };
        const Case cases[] = {
            {"unknown key",
             "[material]\nthreknes = 1\n",
             {"bad.toml:2", "unknown key 'material.threknes'", "(remove it"}},
            {"typo with suggestion", "[material]\nyoung_modulos = 1e9\n", {"did you mean 'material.young_modulus'"}},
            {"unknown section",
             "[materal]\nyoung_modulus = 1e9\n",
             {"bad.toml:1", "unknown section [materal]", "did you mean 'material'"}},
            {"wrong type",
             "[material]\nyoung_modulus = \"high\"\n",
             {"bad.toml:2", "must be a number", "not a string"}},
            {"wrong array type", "[surface]\nsize = [\"a\", 1]\n", {"bad.toml:2", "array of numbers"}},
            {"out of range",
             "[material]\npoisson_ratio = 0.5\n",
             {"bad.toml:2", "poisson_ratio = 0.5", "[-0.99, 0.5)"}},
            {"negative thickness", "[material]\nthickness = [-0.01, 0.01]\n", {"bad.toml:2", "thickness"}},
            {"zero modulus", "[material]\nyoung_modulus = 0\n", {"bad.toml:2", "(0, 1e+13]"}},
            {"absurd size",
             "[simulation]\nelements = 3000000\n",
             {"bad.toml:2", "elements = 3000000", "[32, 2000000]"}},
            {"fractional integer", "[simulation]\nelements = 1000.5\n", {"bad.toml:2", "whole number"}},
            {"bad enum", "[surface]\nkind = \"torus\"\n", {"bad.toml:2", "plane | cylinder | sphere"}},
            {"malformed TOML", "[material]\nyoung_modulus = = 3\n", {"bad.toml:2", "malformed TOML"}},
            {"section as value", "surface = 3\n", {"bad.toml:1", "is a section"}},
            {"wrong array length", "[material]\nshrinkage = [0.1]\n", {"bad.toml:2", "2 elements"}},
            {"sphere size", "[surface]\nkind = \"sphere\"\nsize = [0.1, 0.2]\n", {"bad.toml:3", "[radius]"}},
            {"slanted trunk growth", "[growth]\nangle_deg = 30\n", {"bad.toml:2", "use 0"}},
            {"collapsing background",
             "[growth]\nkind = \"isogonic\"\nrate = [-2.0, -2.0]\n",
             {"bad.toml:3", "shrinks the background"}},
            {"missing image",
             "[variation.toughness]\npattern = \"image\"\nimage = \"nope.png\"\n",
             {"bad.toml:3", "nope.png", "not found"}},
            {"image pattern without image",
             "[variation.toughness]\npattern = \"image\"\n",
             {"bad.toml:2", "needs an image"}},
            {"missing parent",
             "extends = \"no-such-preset\"\n",
             {"bad.toml:1", "preset 'no-such-preset' not found", "built-in presets:"}},
        };
        for (const Case& c : cases) {
            CAPTURE(c.what);
            test::write_text(dir / "bad.toml", c.toml);
            const std::string msg = load_error((dir / "bad.toml").string());
            CAPTURE(msg);
            REQUIRE_FALSE(msg.empty());
            for (const auto& part : c.expected)
                CHECK(contains(msg, part));
            CHECK(contains(msg, "(")); // every message says how to fix it
        }
    }

    TEST_CASE("preset: a missing preset file and an extends cycle are reported") {
        CHECK(contains(load_error("/no/such/dir/preset.toml"), "not found"));
        CHECK(contains(load_error("barc"), "did you mean 'bark'"));
        const auto dir = test::scratch_dir("preset-cycle");
        test::write_text(dir / "a.toml", "extends = \"b\"\n");
        test::write_text(dir / "b.toml", "extends = \"a\"\n");
        CHECK(contains(load_error((dir / "a.toml").string()), "cycle"));
    }

    TEST_CASE("preset: `presets show` output is itself a preset that loads to the same values") {
        const io::Preset p = load("mud/thickness-gradient", {"simulation.seed=77"});
        const std::string text = p.to_toml();
        const auto dir = test::scratch_dir("preset-roundtrip");
        test::write_text(dir / "resolved.toml", text);
        const io::Preset q = load((dir / "resolved.toml").string());
        for (const io::KeySpec& k : io::preset_schema()) {
            CAPTURE(k.name());
            CHECK(io::to_toml(p.entry(k.name()).value) == io::to_toml(q.entry(k.name()).value));
        }
        CHECK(contains(text, "# from") == false);
        CHECK(contains(text, "from: --set"));
    }

    TEST_CASE("preset: docs/presets.md is generated from the schema and up to date") {
        const std::string on_disk = test::slurp(fs::path(CRACKLE_SOURCE_DIR) / "docs" / "presets.md");
        CHECK_MESSAGE(on_disk == io::schema_markdown(),
                      "docs/presets.md is stale: regenerate it with `build/crackle presets doc > docs/presets.md`");
    }

    TEST_CASE("preset schema: every default passes its own checks and every key is documented") {
        for (const io::KeySpec& k : io::preset_schema()) {
            CAPTURE(k.name());
            CHECK(io::check_value(k, k.default_value) == "");
            CHECK(k.description.size() > 20);
        }
    }
}
