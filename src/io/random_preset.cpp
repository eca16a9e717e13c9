#include "io/random_preset.hpp"

#include "core/rng.hpp"
#include "io/preset_schema.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <vector>

namespace crackle::io {

namespace {

constexpr std::uint64_t kSoakStream = 1601; // issue 16; apart from the pipeline's streams

/// A value in [lo, hi]: at a bound now and then, log-uniform over ranges of many decades
/// (a Young's modulus from 1 Pa to 1e13 Pa), uniform otherwise.
double draw(Rng& rng, double lo, double hi, bool lo_excl, bool hi_excl, double bound_probability) {
    if (rng.uniform() < bound_probability) {
        if (rng.uniform() < 0.5 && !lo_excl) return lo;
        if (!hi_excl) return hi;
    }
    // Many decades (a Young's modulus up to 1e13 Pa, a tolerance from 1e-14): log-uniform, from
    // 1e-6 of the top where the range starts at 0.
    if (lo >= 0 && hi > 0 && (lo > 0 ? hi / lo > 1e3 : hi > 1e3)) {
        const double a = std::log(lo > 0 ? lo : hi * 1e-6), b = std::log(hi);
        return std::clamp(std::exp(rng.uniform(a, b)), lo, hi);
    }
    double x = rng.uniform(lo, hi);
    if (lo_excl && x <= lo) x = 0.5 * (lo + hi);
    return x;
}

/// Physical sizes a run of a few thousand elements can hold: the schema allows 1000 m tiles.
const std::map<std::string, std::pair<double, double>>& practical_ranges() {
    static const std::map<std::string, std::pair<double, double>> ranges{
        {"surface.size", {0.02, 5.0}},
        {"material.thickness", {1e-4, 0.2}},
        {"material.initiation_length", {0.0, 0.05}},
        {"material.pattern_scale", {0.0, 1.0}}, // sets the thickness: spacing / 1 m ≈ a thickness of 0.2 m
        {"simulation.duration", {0.01, 20.0}},
    };
    return ranges;
}

std::string toml_number(double x) {
    std::ostringstream os;
    os.precision(17);
    os << x;
    std::string s = os.str();
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

} // namespace

namespace {

/// Keeps a drawn preset inside the rules that join keys (docs/presets.md), so that most soak
/// runs run instead of being refused: surface.size has one value on a sphere and two elsewhere,
/// a cylinder's or sphere's linear growth runs around the axis or along it, and growth and shrinkage
/// rates leave the layer more than 5 % of its size over the duration.
void join_keys(Rng& rng, std::map<std::string, std::vector<double>>& nums,
               const std::map<std::string, std::string>& texts) {
    const auto kind_it = texts.find("surface.kind");
    const std::string kind = kind_it == texts.end() ? "\"cylinder\"" : kind_it->second;
    if (auto it = nums.find("surface.size"); it != nums.end()) {
        std::vector<double>& size = it->second;
        size.resize(kind == "\"sphere\"" ? 1 : 2, size.front());
        if (kind == "\"sphere\"") size[0] = std::min(size[0], 2.0);
    }
    if (auto it = nums.find("growth.angle_deg"); it != nums.end() && kind != "\"plane\"")
        it->second = {rng.uniform() < 0.5 ? 0.0 : 90.0};
    const auto d = nums.find("simulation.duration");
    const double duration = d == nums.end() ? 1.0 : d->second.front();
    if (auto it = nums.find("growth.rate"); it != nums.end())
        for (double& r : it->second)
            r = std::max(r, -0.9 / duration);
    if (auto it = nums.find("material.shrinkage"); it != nums.end())
        for (double& r : it->second)
            r = std::min(r, 0.9 / duration);
}

} // namespace

std::string random_preset(std::uint64_t seed, const RandomPresetOptions& o) {
    Rng rng(seed, kSoakStream);
    std::vector<const KeySpec*> drawn;
    std::map<std::string, std::vector<double>> nums; // numbers and arrays
    std::map<std::string, std::string> texts;        // TOML text of the rest
    for (const KeySpec& k : preset_schema()) {
        const std::string name = k.name();
        if (name != "simulation.elements" && rng.uniform() >= o.key_probability) continue;
        double lo = k.min, hi = k.max;
        if (const auto it = practical_ranges().find(name); it != practical_ranges().end()) {
            lo = std::max(lo, it->second.first);
            hi = std::min(hi, it->second.second);
        }
        switch (k.type) {
        case ValueType::Float:
            nums[name] = {draw(rng, lo, hi, k.min_exclusive, k.max_exclusive, o.bound_probability)};
            break;
        case ValueType::Int:
            if (name == "simulation.elements") {
                lo = static_cast<double>(o.min_elements);
                hi = static_cast<double>(o.max_elements);
            } else if (name == "bake.size" || name == "bake.size_v") {
                hi = std::min(hi, static_cast<double>(o.max_bake_size));
            }
            texts[name] = name == "simulation.seed"
                              ? std::to_string(rng.next_u64() % 9000000000000000001ull)
                              : std::to_string(std::llround(draw(rng, lo, hi, false, false, o.bound_probability)));
            break;
        case ValueType::Bool:
            texts[name] = rng.uniform() < 0.5 ? "true" : "false";
            break;
        case ValueType::Enum: {
            std::vector<std::string> choices = k.choices;
            if (k.key == "kind" && k.section == "surface") // the soak has no model file
                choices.erase(std::remove(choices.begin(), choices.end(), "mesh"), choices.end());
            std::string choice = choices[rng.uniform_int(static_cast<std::uint32_t>(choices.size()))];
            if (k.key == "pattern" && choice == "image") choice = "noise"; // the soak has no image file
            texts[name] = "\"" + choice + "\"";
            break;
        }
        case ValueType::FloatArray: {
            const auto n =
                k.min_length
                + static_cast<int>(rng.uniform_int(static_cast<std::uint32_t>(k.max_length - k.min_length + 1)));
            std::vector<double>& a = nums[name];
            for (int i = 0; i < n; ++i)
                a.push_back(draw(rng, lo, hi, k.min_exclusive, false, o.bound_probability));
            break;
        }
        default:
            continue; // file names, output names and map lists keep their defaults
        }
        drawn.push_back(&k);
    }
    // One preset in seven keeps its raw draws, to try the refusals of joined keys too.
    const bool raw = seed % 7 == 0;
    if (!raw) {
        const auto kind = texts.find("surface.kind");
        if (kind != texts.end() && kind->second == "\"sphere\"" && !nums.count("surface.size")) {
            nums["surface.size"] = {rng.uniform(0.02, 2.0)}; // the default size is a plane's
            drawn.push_back(find_key("surface.size"));
        }
        join_keys(rng, nums, texts);
    }

    std::map<std::string, std::vector<std::string>> sections; // section -> "key = value" lines
    for (const KeySpec* k : drawn) {
        std::string value;
        if (const auto it = nums.find(k->name()); it != nums.end()) {
            const bool array = k->type == ValueType::FloatArray;
            value = array ? "[" : "";
            for (std::size_t i = 0; i < it->second.size(); ++i)
                value += (i ? ", " : "") + toml_number(it->second[i]);
            if (array) value += "]";
        } else {
            value = texts.at(k->name());
        }
        sections[k->section].push_back(k->key + " = " + value);
    }
    std::ostringstream os;
    os << "# crackle presets random " << seed << " (a soak-test preset, issue 16" << (raw ? "; raw draws" : "")
       << ")\n";
    for (const auto& [section, lines] : sections) {
        os << "\n[" << section << "]\n";
        for (const std::string& line : lines)
            os << line << "\n";
    }
    return os.str();
}

} // namespace crackle::io
