// The shipped preset library (presets/, issue 13): every built-in preset loads, simulates and
// bakes at a tiny size; key presets keep their pattern's character over seeds (statistics bands,
// so a physics regression shows as a preset failing); material.pattern_scale sets the thickness
// from the measured spacing ratio and doubling it doubles the spacing.
#include "core/json.hpp"
#include "io/preset.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"
#include "support/presets.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

using Stats = std::map<std::string, double>;

/// Runs `crackle <command> <preset> args…` and returns the report's numeric fields.
Stats run_report(const std::string& command, const std::string& preset, std::vector<std::string> args) {
    const fs::path dir = test::scratch_dir("presets-library");
    std::vector<std::string> cli = {"-q", command, preset, "--json", (dir / "r.json").string()};
    cli.insert(cli.end(), args.begin(), args.end());
    const auto r = test::run_cli(cli);
    REQUIRE_MESSAGE(r.code == 0, preset << ": " << r.err);
    const Json report = Json::parse(test::slurp(dir / "r.json"), (dir / "r.json").string());
    Stats s;
    for (const auto& [key, value] : report.members())
        if (value.is_number()) s[key] = value.as_number();
    return s;
}

/// Mean of a report field over seeds 1, 2, 3.
struct SeedRuns {
    std::vector<Stats> runs;
    double mean(const std::string& key) const {
        double sum = 0;
        for (const Stats& s : runs)
            sum += s.at(key);
        return sum / double(runs.size());
    }
    double min(const std::string& key) const {
        double m = runs.front().at(key);
        for (const Stats& s : runs)
            m = std::min(m, s.at(key));
        return m;
    }
};

SeedRuns over_seeds(const std::string& preset, const std::string& elements,
                    const std::vector<std::string>& extra = {}) {
    SeedRuns out;
    for (const char* seed : {"1", "2", "3"}) {
        std::vector<std::string> args = {"--seed", seed, "--set", "simulation.elements=" + elements};
        args.insert(args.end(), extra.begin(), extra.end());
        out.runs.push_back(run_report("simulate", preset, args));
    }
    return out;
}

/// The artist's crack spacing: (2 − anisotropy) / crack density (2/ρ for a network, 1/ρ for
/// parallel fissures), as material.pattern_scale defines it.
double spacing(const Stats& s) {
    return (2.0 - s.at("anisotropy")) / s.at("crack_length_per_area");
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("preset library: every built-in preset loads, simulates and bakes at a tiny size") {
        // bake.size = 32 caps "auto" at its floor (400 elements, or what a curved surface needs),
        // so the whole library runs in about SMOKE_SECONDS s on one core (measured).
        const bool gl = test::gl_context_or_skip() != nullptr;
        const auto names = io::builtin_preset_names();
        CHECK(names.size() >= 30);
        for (const std::string& name : names) {
            CAPTURE(name);
            const io::Preset p = test::load(name, {"simulation.elements=auto", "bake.size=32"});
            CHECK(p.is_auto("simulation.elements"));
            const fs::path out = test::scratch_dir("presets-library-bake");
            // Without the tip sub-model (mud's 4× cost); every shipped preset is fem-split.
            std::vector<std::string> args = {"--set", "simulation.elements=auto", "--set", "bake.size=32",
                                             "--set", "simulation.tip_submodel=0"};
            if (gl) args.insert(args.end(), {"--out", out.string()});
            const Stats s = run_report(gl ? "bake" : "simulate", name, args);
            CHECK(s.at("elements_initial") <= 1000);
            CHECK(s.at("fragments") >= 1);
            CHECK(std::isfinite(s.at("crack_length_per_area")));
            if (!gl) continue;
            int maps = 0;
            for (const auto& f : fs::directory_iterator(out))
                maps += f.path().extension() == ".png" ? 1 : 0;
            CHECK(maps >= 4);
        }
    }

    TEST_CASE("preset library: key presets keep their pattern's statistics over seeds") {
        // Bands around the means over seeds 1-3 at reduced element counts, measured with
        //   crackle -q simulate <preset> --seed S --set simulation.elements=N [--set ...] --json r.json
        // (2026-12, with the initiation stress averaged over the layer thickness and its nucleus). Seed spreads are a
        // few per cent; the bands are about ±15 %, so a physics regression (not noise) moves a preset out of its band.

        // Mud on a quarter tile (0.25 m, 400 elements, the tip sub-model kept): T-junctions
        // 0.777 / 0.667 / 0.724 (0.703 / 0.550 / 0.587 without the sub-model; junctions counted
        // with hanging-node splits merged, 2026-12-05), crack density 68.8 / 66.4 / 67.7 per m,
        // anisotropy 0.023 / 0.007 / 0.018. About 3.5 s a seed.
        const SeedRuns mud = over_seeds("mud", "400", {"--set", "surface.size=[0.25,0.25]"});
        CHECK(mud.min("t_junction_fraction") >= 0.60);
        CHECK(mud.mean("t_junction_fraction") >= 0.65);
        CHECK(mud.mean("crack_length_per_area") == doctest::Approx(71.5).epsilon(0.15));
        CHECK(mud.mean("anisotropy") <= 0.1);

        // The default bark at 800 elements: fragments 6 / 13 / 9, density 35.1 / 34.7 / 34.5,
        // anisotropy 0.891 / 0.882 / 0.906, axial share 0.927 / 0.937 / 0.946. About 1 s a seed.
        const SeedRuns bark = over_seeds("bark", "800");
        CHECK(bark.mean("fragments") >= 5);
        CHECK(bark.mean("fragments") <= 20);
        CHECK(bark.mean("crack_length_per_area") == doctest::Approx(35.5).epsilon(0.12));
        CHECK(bark.min("anisotropy") >= 0.85);
        CHECK(bark.min("axial_fraction") >= 0.9);

        // Flowering dogwood (small blocks) at 800: fragments 173 / 175 / 172, density 101.5 /
        // 99.9 / 101.2, anisotropy 0.431 / 0.432 / 0.421. About 2 s a seed.
        const SeedRuns dogwood = over_seeds("bark/flowering-dogwood", "800");
        CHECK(dogwood.mean("fragments") == doctest::Approx(173).epsilon(0.15));
        CHECK(dogwood.mean("crack_length_per_area") == doctest::Approx(100.9).epsilon(0.12));
        CHECK(dogwood.mean("anisotropy") >= 0.25);
        CHECK(dogwood.mean("anisotropy") <= 0.5);

        // Black hickory (narrow ridges) at 800: fragments 46 / 46 / 51, density 46.5 / 46.6 /
        // 44.7, anisotropy 0.799 / 0.816 / 0.787, axial share 0.862 / 0.873 / 0.857. About 2.5 s a seed.
        const SeedRuns hickory = over_seeds("bark/black-hickory", "800");
        CHECK(hickory.mean("fragments") == doctest::Approx(48).epsilon(0.2));
        CHECK(hickory.mean("crack_length_per_area") == doctest::Approx(45.9).epsilon(0.12));
        CHECK(hickory.mean("anisotropy") >= 0.6);
        CHECK(hickory.mean("anisotropy") <= 0.85);
        CHECK(hickory.min("axial_fraction") >= 0.7);
        // The species differ as they should: dogwood's blocks are far smaller than hickory's strips.
        CHECK(dogwood.mean("fragments") > 2 * hickory.mean("fragments"));
        CHECK(hickory.mean("anisotropy") > dogwood.mean("anisotropy") + 0.2);

        // The isogonic sphere at 800, with its tip sub-model (2026-12-07): anisotropy 0.037 /
        // 0.033 / 0.024 (the orientation tensor's eigenvalue ratio (1 − a)/(1 + a) near 1),
        // fragments 99 / 99 / 99, density 117.6 / 118.9 / 116.9 (without the sub-model: 101 / 99 /
        // 104 and 117.2 / 115.6 / 119.0). About 1.7 s a seed.
        const SeedRuns sphere = over_seeds("sphere/isogonic", "800");
        CHECK(sphere.mean("anisotropy") <= 0.06);
        for (const Stats& s : sphere.runs)
            CHECK((1 - s.at("anisotropy")) / (1 + s.at("anisotropy")) >= 0.85);
        CHECK(sphere.mean("fragments") == doctest::Approx(101).epsilon(0.15));
        CHECK(sphere.mean("crack_length_per_area") == doctest::Approx(117.3).epsilon(0.12));
    }

    TEST_CASE("preset library: material.pattern_scale sets the thickness from the measured spacing ratio") {
        // The calibrated thickness: the spacing over the surface's ratio, a ramp keeping its shape.
        const double plane = io::pattern_spacing_per_thickness("plane");
        const double cylinder = io::pattern_spacing_per_thickness("cylinder");
        CHECK(plane == doctest::Approx(2.73));
        CHECK(cylinder == doctest::Approx(2.11));
        CHECK(io::pattern_spacing_per_thickness("sphere") == doctest::Approx(4.8));
        const io::Preset mud = test::load("mud", {"material.pattern_scale=0.05"});
        CHECK(mud.numbers("material.thickness")[0] == doctest::Approx(0.05 / plane));
        CHECK(mud.numbers("material.thickness")[1] == doctest::Approx(0.05 / plane));
        CHECK(mud.entry("material.thickness").source.text() == "material.pattern_scale at --set");
        const io::Preset bark = test::load("bark", {"material.pattern_scale=0.04"});
        CHECK(bark.numbers("material.thickness")[0] == doctest::Approx(0.04 / cylinder));
        const io::Preset ramp = test::load("mud/thickness-gradient", {"material.pattern_scale=0.1"});
        const auto& t = ramp.numbers("material.thickness");
        CHECK(0.5 * (t[0] + t[1]) == doctest::Approx(0.1 / plane));
        CHECK(t[1] / t[0] == doctest::Approx(4.0)); // 1 → 4 cm keeps its shape
        // 0 (the default) leaves material.thickness alone; the key refuses negative spacings.
        CHECK(test::load("mud").numbers("material.thickness")[0] == 0.01);
        CHECK(test::load_error("mud", {"material.pattern_scale=-0.1"}).find("pattern_scale") != std::string::npos);

        // Doubling the scale doubles the measured spacing, (2 − anisotropy) / crack density, over
        // seeds. Mud without the tip sub-model (its spacing is the same within 5 %), auto elements
        // (1404 and 400), measured: 0.05 → 0.0496 / 0.0503 / 0.0500 m, 0.1 → 0.1028 / 0.1044 /
        // 0.0988 m. About 3 s a seed.
        double small = 0, large = 0;
        for (const char* seed : {"1", "2"}) {
            const std::vector<std::string> common = {"--seed", seed, "--set", "simulation.tip_submodel=0"};
            auto with = [&](const char* scale) {
                std::vector<std::string> args = common;
                args.insert(args.end(), {"--set", std::string("material.pattern_scale=") + scale});
                return spacing(run_report("simulate", "mud", args));
            };
            small += with("0.05") / 2;
            large += with("0.1") / 2;
        }
        CAPTURE(small);
        CAPTURE(large);
        CHECK(small == doctest::Approx(0.05).epsilon(0.15));
        CHECK(large == doctest::Approx(0.1).epsilon(0.15));
        CHECK(large / small == doctest::Approx(2.0).epsilon(0.15));
    }
}
