#pragma once
/// @file Presets: TOML files (toml++) checked against the schema, resolved through
/// `extends`, defaults and `--set` overrides before any work starts.

#include "io/preset_schema.hpp"

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace crackle::io {

/// Where a value came from: "presets/bark.toml:12", "--set", or "default".
struct SourceLocation {
    std::string file; ///< file name as given, "--set", or "" for the default
    int line = 0;

    std::string text() const;
};

struct PresetValue {
    Value value;
    SourceLocation source;
    std::filesystem::path base_dir; ///< folder that relative paths (images) resolve against
};

class Preset : public Settings {
public:
    std::string name; ///< as requested: "bark", "my/preset.toml"

    double number(const std::string& key) const override;
    std::int64_t integer(const std::string& key) const override;
    bool flag(const std::string& key) const override;
    const std::string& text(const std::string& key) const override;
    const std::vector<double>& numbers(const std::string& key) const override;
    bool is_auto(const std::string& key) const override;
    const PresetValue& entry(const std::string& key) const;
    /// A path-valued key resolved against the folder of the preset that set it.
    std::filesystem::path path(const std::string& key) const;

    void set(const std::string& key, PresetValue value) { m_values[key] = std::move(value); }
    /// Every key with its value, sorted by key.
    const std::map<std::string, PresetValue>& values() const { return m_values; }

    /// The fully resolved preset as TOML, every key with its unit, range, description and
    /// where its value came from.
    std::string to_toml() const;

private:
    std::map<std::string, PresetValue> m_values;
};

/// A value one of the command line's own flags gives a key (`--size` gives bake.size and
/// bake.size_v, `--maps` bake.maps): typed, checked as the preset's values are, its source the flag.
struct FlagValue {
    std::string key;  ///< "bake.size"
    Value value;      ///< of the key's type
    std::string flag; ///< "--size": where an error or the report's provenance says it came from
    /// Applied just before overrides[at] (0: under every --set; the default: after them all).
    std::size_t at = static_cast<std::size_t>(-1);
};

/// A request to load a preset.
struct PresetRequest {
    std::string name_or_path;           ///< built-in name ("bark", "mud/thick") or a .toml path
    std::vector<std::string> overrides; ///< "section.key=value" (--set)
    std::int64_t seed = -1;             ///< --seed; < 0 keeps simulation.seed
    std::vector<FlagValue> flags = {};  ///< --size, --maps, --bit-depth, --preview's map size
};

/// Loads, inherits, checks and completes a preset. Throws InputError with
/// "<file>:<line>: <what> (<how to fix>)" on any problem.
Preset load_preset(const PresetRequest& request);

/// The loaded preset with more "section.key=value" overrides applied, checked as --set checks them
/// (the preview's reduced model: no file is read again). Not for material.thickness or
/// material.pattern_scale, which the loader derives one from the other.
Preset with_overrides(const Preset& preset, const std::vector<std::string>& overrides);

/// material.pattern_scale's calibration: the crack spacing ((2 − anisotropy) / crack density)
/// per layer thickness measured on the default preset of a surface kind (plane: mud, cylinder:
/// bark; docs/presets-library.md). A pattern scale s sets the mean thickness to s / ratio.
double pattern_spacing_per_thickness(const std::string& surface_kind);

/// Built-in preset names (embedded presets/ folder), sorted.
std::vector<std::string> builtin_preset_names();
/// First comment line of a built-in preset (its one-line summary), or "".
std::string builtin_preset_summary(const std::string& name);

} // namespace crackle::io
