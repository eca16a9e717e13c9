#pragma once
/// @file The preset schema: every key's type, default, unit, range and one-line
/// description. `presets show`, docs/presets.md and all validation come from this table.

#include "core/settings.hpp"

#include <string>
#include <vector>

namespace crackle::io {

using crackle::KeySpec;
using crackle::Value;
using crackle::ValueType;

/// All keys, in documentation order.
const std::vector<KeySpec>& preset_schema();

/// The spec of "section.key", or nullptr.
const KeySpec* find_key(const std::string& full_name);

/// Sections in documentation order, with a one-line description each.
const std::vector<std::pair<std::string, std::string>>& preset_sections();

/// "[0, 0.5)", "(0, 1e+13]", "plane | cylinder | sphere"
std::string range_text(const KeySpec& spec);

/// Checks a value against the spec's range, choices and length. Returns "" when valid,
/// else what is wrong ("must be in (0, 1e13]").
std::string check_value(const KeySpec& spec, const Value& value);

/// TOML text of a value ("0.3", "[0.5, 0.5]", "\"cylinder\"").
std::string to_toml(const Value& value);

/// The Markdown reference (docs/presets.md), generated from the schema.
std::string schema_markdown();

} // namespace crackle::io
