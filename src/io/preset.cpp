#include "io/preset.hpp"

#include "core/atomic_file.hpp"
#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/math.hpp"
#include "core/strings.hpp"
#include "io/resolution.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <sstream>
#include <stdexcept>

namespace crackle::io {

namespace fs = std::filesystem;

std::string SourceLocation::text() const {
    if (file.empty()) return "default";
    if (line <= 0) return file;
    return file + ":" + std::to_string(line);
}

// === Typed access

const PresetValue& Preset::entry(const std::string& key) const {
    const auto it = m_values.find(key);
    CRACKLE_ASSERT(it != m_values.end(), "preset has no key '" << key << "' (not in the schema?)");
    return it->second;
}

double Preset::number(const std::string& key) const {
    return std::get<double>(entry(key).value);
}
std::int64_t Preset::integer(const std::string& key) const {
    return std::get<std::int64_t>(entry(key).value);
}
bool Preset::flag(const std::string& key) const {
    return std::get<bool>(entry(key).value);
}
const std::string& Preset::text(const std::string& key) const {
    return std::get<std::string>(entry(key).value);
}
const std::vector<double>& Preset::numbers(const std::string& key) const {
    return std::get<std::vector<double>>(entry(key).value);
}
bool Preset::is_auto(const std::string& key) const {
    return std::holds_alternative<std::string>(entry(key).value);
}

fs::path Preset::path(const std::string& key) const {
    const PresetValue& v = entry(key);
    const fs::path p = std::get<std::string>(v.value);
    if (p.empty() || p.is_absolute() || v.base_dir.empty()) return p;
    return v.base_dir / p;
}

std::string Preset::to_toml() const {
    std::ostringstream os;
    os << "# Preset '" << name << "', fully resolved: every key with its default, unit and range.\n"
       << "# Each value's origin is noted (default, a preset file:line, or --set).\n";
    for (const auto& [section, about] : preset_sections()) {
        os << "\n[" << section << "]  # " << about << "\n";
        for (const KeySpec& spec : preset_schema()) {
            if (spec.section != section) continue;
            const PresetValue& v = entry(spec.name());
            os << "# " << spec.description << "\n# ";
            if (!spec.unit.empty()) os << "unit: " << spec.unit << "; ";
            os << "range: " << range_text(spec) << "; from: " << v.source.text() << "\n";
            os << spec.key << " = " << io::to_toml(v.value) << "\n";
        }
    }
    return os.str();
}

// === Built-in presets

std::vector<std::string> builtin_preset_names() {
    std::vector<std::string> names;
    for (const EmbeddedFile& f : embedded::presets())
        names.emplace_back(f.name);
    std::sort(names.begin(), names.end());
    return names;
}

std::string builtin_preset_summary(const std::string& name) {
    for (const EmbeddedFile& f : embedded::presets()) {
        if (f.name != name) continue;
        std::istringstream is{std::string(f.text)};
        std::string line;
        while (std::getline(is, line)) {
            if (line.rfind("# ", 0) == 0) return line.substr(2);
            if (!line.empty()) break;
        }
    }
    return {};
}

namespace {

/// A preset's text and where it came from.
struct Source {
    std::string display; ///< name shown in messages: the path, or "builtin:bark.toml"
    std::string text;
    fs::path dir;         ///< folder for relative paths (empty for built-ins)
    std::string identity; ///< for cycle detection
};

bool has_toml_extension(const std::string& s) {
    return s.size() > 5 && s.substr(s.size() - 5) == ".toml";
}

/// Finds a preset by name or path. For `extends`, relative names resolve first against
/// the extending file's folder.
/// `from` is the identity of the file whose `extends` asks for `name`: a user's ./mud.toml that
/// extends "mud" means the built-in, not itself.
Source find_source(const std::string& name, const fs::path& relative_to, const SourceLocation& requested_at,
                   const std::string& from = {}) {
    std::vector<fs::path> candidates;
    const std::string file_name = has_toml_extension(name) ? name : name + ".toml";
    if (!relative_to.empty()) candidates.push_back(relative_to / file_name);
    const bool looks_like_path =
        has_toml_extension(name) || name.find('/') != std::string::npos || name.find('\\') != std::string::npos;
    // A path given on the command line resolves against the working directory.
    if (relative_to.empty() && looks_like_path) candidates.push_back(fs::path(file_name));
    for (const fs::path& c : candidates) {
        std::error_code ec;
        if (fs::is_regular_file(c, ec) && (from.empty() || fs::weakly_canonical(c, ec).string() != from)) {
            Source s;
            s.display = c.lexically_normal().string();
            s.text = read_file(c, "preset file");
            s.dir = c.parent_path();
            s.identity = fs::weakly_canonical(c, ec).string();
            return s;
        }
    }
    const std::string builtin = has_toml_extension(name) ? name.substr(0, name.size() - 5) : name;
    for (const EmbeddedFile& f : embedded::presets()) {
        if (f.name == builtin) {
            Source s;
            s.display = "builtin:" + std::string(f.path);
            s.text = std::string(f.text);
            s.identity = s.display;
            return s;
        }
    }
    const std::vector<std::string> names = builtin_preset_names();
    const std::string list = join(names, ", ");
    throw InputError(requested_at.file.empty() ? std::string("preset") : requested_at.text(),
                     "preset '" + name + "' not found" + did_you_mean(builtin, names),
                     "built-in presets: " + list + "; or give the path of a .toml file");
}

std::vector<std::string> all_key_names() {
    std::vector<std::string> names;
    for (const KeySpec& k : preset_schema())
        names.push_back(k.name());
    return names;
}

bool is_section(const std::string& name) {
    for (const auto& [s, about] : preset_sections())
        if (s == name || s.rfind(name + ".", 0) == 0) return true;
    return false;
}

std::string type_name(const toml::node& node) {
    std::ostringstream os;
    os << node.type();
    return os.str();
}

std::string example_of(const KeySpec& spec) {
    switch (spec.type) {
    case ValueType::Float:
        if (spec.allows_auto) return "\"auto\" or a number such as 0.005";
        return "a number such as " + to_toml(spec.default_value);
    case ValueType::Int:
        if (spec.allows_auto) return "\"auto\" or a whole number such as 8000";
        return "a whole number such as " + to_toml(spec.default_value);
    case ValueType::Bool:
        return "true or false";
    case ValueType::String:
        return "a quoted string";
    case ValueType::Enum:
        return "one of " + range_text(spec) + " in quotes";
    case ValueType::FloatArray:
        return "an array of numbers such as " + to_toml(spec.default_value);
    }
    return "";
}

/// Converts a TOML node to the spec's type; throws InputError at `where` on a mismatch.
Value convert(const KeySpec& spec, const toml::node& node, const std::string& where) {
    auto mismatch = [&]() -> InputError {
        return InputError(where, spec.name() + " must be " + example_of(spec) + ", not a " + type_name(node),
                          "write " + example_of(spec));
    };
    switch (spec.type) {
    case ValueType::Float:
        if (node.is_floating_point()) return *node.value<double>();
        if (node.is_integer()) return static_cast<double>(*node.value<std::int64_t>());
        if (spec.allows_auto && node.is_string()) {
            if (*node.value<std::string>() == "auto") return std::string("auto");
            throw InputError(
                where, spec.name() + " must be " + example_of(spec) + ", not \"" + *node.value<std::string>() + "\"",
                "write " + example_of(spec));
        }
        throw mismatch();
    case ValueType::Int:
        if (node.is_integer()) return *node.value<std::int64_t>();
        if (spec.allows_auto && node.is_string()) {
            if (*node.value<std::string>() == "auto") return std::string("auto");
            throw InputError(
                where, spec.name() + " must be " + example_of(spec) + ", not \"" + *node.value<std::string>() + "\"",
                "write " + example_of(spec));
        }
        if (node.is_floating_point()) {
            const double d = *node.value<double>();
            if (std::isfinite(d) && d == std::floor(d) && std::abs(d) < 9.0e18) return static_cast<std::int64_t>(d);
            throw InputError(where, spec.name() + " must be a whole number, not " + to_toml(d),
                             "write " + example_of(spec));
        }
        throw mismatch();
    case ValueType::Bool:
        if (node.is_boolean()) return *node.value<bool>();
        throw mismatch();
    case ValueType::String:
    case ValueType::Enum:
        if (node.is_string()) return std::string(*node.value<std::string>());
        throw mismatch();
    case ValueType::FloatArray: {
        if (!node.is_array()) throw mismatch();
        std::vector<double> out;
        for (const toml::node& el : *node.as_array()) {
            if (el.is_floating_point())
                out.push_back(*el.value<double>());
            else if (el.is_integer())
                out.push_back(static_cast<double>(*el.value<std::int64_t>()));
            else
                throw InputError(where, spec.name() + " must be an array of numbers; it holds a " + type_name(el),
                                 "write " + example_of(spec));
        }
        return out;
    }
    }
    throw mismatch();
}

/// Checks range/choices; throws InputError naming the value and how to fix it.
void check(const KeySpec& spec, const Value& value, const std::string& where) {
    const std::string problem = check_value(spec, value);
    if (problem.empty()) return;
    std::string extra;
    if (spec.type == ValueType::Enum) extra = did_you_mean(std::get<std::string>(value), spec.choices);
    throw InputError(where, spec.name() + " = " + to_toml(value) + " " + problem + extra,
                     spec.type == ValueType::Enum ? "use one of " + range_text(spec)
                                                  : "set a value in range; " + spec.description);
}

using Values = std::map<std::string, PresetValue>;

void load_recursive(const std::string& name, const fs::path& relative_to, const SourceLocation& requested_at,
                    std::vector<std::string>& chain, Values& values) {
    const Source src = find_source(name, relative_to, requested_at, chain.empty() ? std::string() : chain.back());
    if (std::find(chain.begin(), chain.end(), src.identity) != chain.end()) {
        std::string cycle;
        for (const auto& c : chain)
            cycle += c + " -> ";
        throw InputError(requested_at.text(), "'extends' forms a cycle: " + cycle + src.identity,
                         "remove the extends line that closes the loop");
    }
    chain.push_back(src.identity);

    toml::table table;
    try {
        table = toml::parse(std::string_view(src.text), std::string_view(src.display));
    } catch (const toml::parse_error& e) {
        throw InputError(src.display + ":" + std::to_string(e.source().begin.line),
                         "malformed TOML: " + std::string(e.description()),
                         "fix the syntax; see docs/presets.md for the format");
    }
    auto where = [&](const toml::node& node) { return src.display + ":" + std::to_string(node.source().begin.line); };

    // === Parent first, then this file's values on top
    if (const toml::node* ext = table.get("extends")) {
        if (!ext->is_string())
            throw InputError(where(*ext), "extends must be a preset name in quotes", "write extends = \"bark\"");
        load_recursive(std::string(*ext->value<std::string>()), src.dir,
                       {src.display, static_cast<int>(ext->source().begin.line)}, chain, values);
    }

    // === Flatten nested tables into "section.key" leaves and check each against the schema
    const std::vector<std::string> names = all_key_names();
    std::function<void(const toml::table&, const std::string&)> walk = [&](const toml::table& t,
                                                                           const std::string& prefix) {
        for (auto&& [k, node] : t) {
            const std::string full = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
            if (prefix.empty() && full == "extends") continue;
            const KeySpec* spec = find_key(full);
            if (!spec && node.is_table()) {
                if (!is_section(full)) {
                    std::vector<std::string> sections;
                    for (const auto& [s, about] : preset_sections())
                        sections.push_back(s);
                    throw InputError(
                        where(node), "unknown section [" + full + "]" + did_you_mean(full, sections),
                        "sections are: " + [&] {
                            std::string l;
                            for (const auto& s : sections)
                                l += (l.empty() ? "" : ", ") + s;
                            return l;
                        }() + " (docs/presets.md)");
                }
                walk(*node.as_table(), full);
                continue;
            }
            if (!spec) {
                if (is_section(full))
                    throw InputError(where(node), "'" + full + "' is a section, not a value",
                                     "write it as a table: [" + full + "]");
                throw InputError(where(node), "unknown key '" + full + "'" + did_you_mean(full, names),
                                 "remove it or check the spelling; `crackle presets show` lists every key");
            }
            const Value value = convert(*spec, node, where(node));
            check(*spec, value, where(node));
            values[full] = PresetValue{value, {src.display, static_cast<int>(node.source().begin.line)}, src.dir};
        }
    };
    walk(table, "");
    chain.pop_back();
}

void apply_override(const std::string& assignment, Values& values) {
    const std::string where = "--set " + assignment;
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
        throw InputError(where, "expected section.key=value", "for example --set material.thickness=[0.02,0.02]");
    const std::string key = assignment.substr(0, eq);
    const std::string raw = assignment.substr(eq + 1);
    const KeySpec* spec = find_key(key);
    if (!spec)
        throw InputError(where, "unknown key '" + key + "'" + did_you_mean(key, all_key_names()),
                         "`crackle presets show` lists every key");
    Value value;
    toml::table parsed;
    bool parsed_ok = true;
    try {
        parsed = toml::parse(std::string_view("v = " + raw), std::string_view("--set"));
    } catch (const toml::parse_error&) {
        parsed_ok = false;
    }
    if (parsed_ok && parsed.get("v")
        && !((spec->type == ValueType::String || spec->type == ValueType::Enum) && !parsed.get("v")->is_string())) {
        value = convert(*spec, *parsed.get("v"), where);
    } else if (spec->type == ValueType::String || spec->type == ValueType::Enum) {
        value = raw; // bare words are fine for text: --set surface.kind=plane
    } else if (spec->allows_auto && raw == "auto") {
        value = std::string("auto"); // --set simulation.elements=auto
    } else {
        throw InputError(where, "'" + raw + "' is not a valid value for " + key, "write " + example_of(*spec));
    }
    check(*spec, value, where);
    PresetValue from_cli;
    from_cli.value = value;
    from_cli.source = SourceLocation{"--set", 0};
    from_cli.base_dir = fs::current_path();
    values[key] = std::move(from_cli);
}

void apply_flag(const FlagValue& flag, Values& values) {
    const KeySpec* spec = find_key(flag.key);
    if (!spec) throw std::logic_error("the flag " + flag.flag + " sets " + flag.key + ", which no preset has");
    check(*spec, flag.value, flag.flag);
    PresetValue from_cli;
    from_cli.value = flag.value;
    from_cli.source = SourceLocation{flag.flag, 0};
    values[flag.key] = std::move(from_cli);
}

/// Checks that involve more than one key.
void check_consistency(const Preset& p) {
    auto at = [&](const std::string& key) { return p.entry(key).source.text(); };
    const std::string kind = p.text("surface.kind");
    const auto& size = p.numbers("surface.size");
    // A model's own size and curvature are checked when it is read (io::read_model).
    const bool model = kind == "mesh";
    if (model && p.text("surface.file").empty())
        throw InputError(at("surface.kind"), "a mesh surface needs its model",
                         "set surface.file to a model file (glTF, OBJ, FBX, ...) relative to the preset");
    if (model) {
        std::error_code ec;
        if (!fs::is_regular_file(p.path("surface.file"), ec))
            throw InputError(at("surface.file"), "model file '" + p.path("surface.file").string() + "' not found",
                             "paths are relative to the preset file that names them");
    }
    if (kind == "sphere" && size.size() != 1)
        throw InputError(at("surface.size"), "a sphere's surface.size is [radius], got " + to_toml(size),
                         "write size = [0.05] for a 5 cm radius");
    if (!model && kind != "sphere" && size.size() != 2)
        throw InputError(at("surface.size"), "a " + kind + "'s surface.size needs two values, got " + to_toml(size),
                         kind == "plane" ? "write size = [width, height]" : "write size = [circumference, height]");
    if (!model && kind != "sphere") {
        const double aspect = std::max(size[0], size[1]) / std::min(size[0], size[1]);
        if (aspect > 1000)
            throw InputError(at("surface.size"),
                             "surface.size " + to_toml(size) + " is a sliver (aspect " + to_toml(aspect) + ")",
                             "keep the aspect ratio below 1000");
    }

    // A curved surface must be resolved: with fewer than about six triangles around, a triangle
    // spans more than 60° of arc and its wedge turns inside out (a stability sweep found a
    // 0.5 m × 50 m trunk failing at 5000 elements, about 4.7 around, and running at 10000).
    if (!model && kind != "plane" && !p.is_auto("simulation.elements")) {
        const double around = kind == "sphere" ? 2 * PI * size[0] : size[0];
        const auto needed = minimum_elements(p);
        const auto elements = p.integer("simulation.elements");
        if (elements < needed)
            throw InputError(at("simulation.elements"),
                             "simulation.elements = " + std::to_string(elements) + " is too coarse for a " + kind + " "
                                 + to_toml(around) + " m around: its triangles would span more than a sixth "
                                 + "of the way around and the layer's elements turn inside out",
                             "use at least " + std::to_string(needed) + " elements"
                                 + (kind == "cylinder" ? ", or a shorter cylinder" : "") + ", or \"auto\"");
    }

    const std::string growth = p.text("growth.kind");
    const double angle = p.number("growth.angle_deg");
    if (growth == "anisotropic" && kind != "plane" && !model) {
        const double a = std::fmod(std::abs(angle), 180.0);
        if (a != 0.0 && a != 90.0)
            throw InputError(at("growth.angle_deg"),
                             "growth.angle_deg = " + to_toml(angle) + " on a " + kind
                                 + ": a linear field there can grow around the axis or along it, not at a slant",
                             "use 0 (r1 around the axis) or 90 (r1 along it)");
    }
    const double duration = p.number("simulation.duration");
    if (growth != "none") {
        const auto& rate = p.numbers("growth.rate");
        const double r_min = growth == "isogonic" ? rate[0] : std::min(rate[0], rate[1]);
        if (1.0 + duration * r_min <= 0.05)
            throw InputError(at("growth.rate"),
                             "growth.rate " + to_toml(rate) + " over simulation.duration " + to_toml(duration)
                                 + " shrinks the background to nothing (1 + r·t ≤ 0.05)",
                             "use a rate above " + to_toml(-0.95 / duration) + " or a shorter duration");
    }
    const auto& shrink = p.numbers("material.shrinkage");
    for (double s : shrink)
        if (1.0 - duration * s <= 0.05)
            throw InputError(at("material.shrinkage"),
                             "material.shrinkage " + to_toml(shrink) + " over simulation.duration " + to_toml(duration)
                                 + " shrinks the layer to nothing (1 − s·t ≤ 0.05)",
                             "use rates below " + to_toml(0.95 / duration) + " or a shorter duration");

    for (const auto& [section, about] : preset_sections()) {
        if (section.rfind("variation.", 0) != 0) continue;
        if (p.text(section + ".pattern") != "image") continue;
        const std::string key = section + ".image";
        if (p.text(key).empty())
            throw InputError(at(section + ".pattern"), section + ".pattern = \"image\" needs an image file",
                             "set " + key + " = \"path/to/map.png\"");
        std::error_code ec;
        if (!fs::is_regular_file(p.path(key), ec))
            throw InputError(at(key), "image file '" + p.path(key).string() + "' not found",
                             "paths are relative to the preset file that names them");
    }
}

/// material.pattern_scale > 0 replaces material.thickness by the thickness whose measured crack
/// spacing is the pattern scale, keeping a ramp's shape (both ends scaled to the wanted mean).
void apply_pattern_scale(Preset& p) {
    const double scale = p.number("material.pattern_scale");
    if (scale <= 0) return;
    const PresetValue& thickness = p.entry("material.thickness");
    std::vector<double> t = std::get<std::vector<double>>(thickness.value);
    const double mean = 0.5 * (t[0] + t[1]);
    const double wanted = scale / pattern_spacing_per_thickness(p.text("surface.kind"));
    for (double& x : t)
        x *= wanted / mean;
    const KeySpec* spec = find_key("material.thickness");
    const PresetValue& from = p.entry("material.pattern_scale");
    check(*spec, t, from.source.text() + " (material.pattern_scale sets material.thickness)");
    p.set("material.thickness", PresetValue{t, {"material.pattern_scale at " + from.source.text(), 0}, from.base_dir});
}

} // namespace

double pattern_spacing_per_thickness(const std::string& surface_kind) {
    // Crack spacing per layer thickness, the mean over seeds 1 and 2 at three or four thicknesses
    // of each surface's default preset at its auto resolution (docs/presets-library.md, "Pattern
    // scale"; re-measured 2026-12-07 after the seam fix and the presets' converged densities).
    constexpr double PLANE = 2.73;    // mud, 1–3 cm: 2.62–2.80
    constexpr double CYLINDER = 2.11; // bark, 1–3 cm: 1.73–2.38 (rising with h/R)
    constexpr double SPHERE = 4.8;    // sphere/isogonic, 4–8 mm on a 5 cm radius: 4.25–5.74 (rising with h/R)
    if (surface_kind == "cylinder") return CYLINDER;
    if (surface_kind == "sphere") return SPHERE;
    return PLANE;
}

Preset with_overrides(const Preset& preset, const std::vector<std::string>& overrides) {
    Values values = preset.values();
    for (const std::string& o : overrides) {
        const std::string key = o.substr(0, o.find('='));
        if (key == "material.thickness" || key == "material.pattern_scale")
            throw std::logic_error("with_overrides: " + key + " feeds material.pattern_scale; load the preset anew");
        apply_override(o, values);
    }
    Preset changed;
    changed.name = preset.name;
    for (auto& [key, value] : values)
        changed.set(key, std::move(value));
    check_consistency(changed);
    return changed;
}

Preset load_preset(const PresetRequest& request) {
    Values values;
    std::vector<std::string> chain;
    load_recursive(request.name_or_path, {}, {}, chain, values);
    for (std::size_t i = 0; i <= request.overrides.size(); ++i) {
        for (const FlagValue& f : request.flags)
            if (std::min(f.at, request.overrides.size()) == i) apply_flag(f, values);
        if (i < request.overrides.size()) apply_override(request.overrides[i], values);
    }
    if (request.seed >= 0) apply_flag({"simulation.seed", request.seed, "--seed"}, values);

    Preset preset;
    preset.name = request.name_or_path;
    for (const KeySpec& spec : preset_schema()) {
        auto it = values.find(spec.name());
        if (it != values.end()) {
            preset.set(spec.name(), it->second);
        } else {
            PresetValue by_default; // source.file stays empty: "default"
            by_default.value = spec.default_value;
            preset.set(spec.name(), by_default);
        }
    }
    apply_pattern_scale(preset);
    check_consistency(preset);
    return preset;
}

} // namespace crackle::io
