#pragma once
/// @file Output names: a name pattern (bake.name, `--name`) with the fields {preset}, {seed},
/// {variant} and {map}, expanded and checked so that no name leaves the output folder.
///
/// Map files are the pattern with {map} = the map's suffix ("Color", "NormalGL", ...); without a
/// {map} field, "_{map}" is appended (ambientCG naming: mud_Color.png). The *base* name (the
/// report <base>.json, meshes <base>.glb) is the pattern with {map} and one separator next to
/// it removed: "{preset}_{seed}_{map}" → "mud_3".

#include "io/texture_set.hpp"

#include <cstdint>
#include <filesystem>
#include <string>

namespace crackle::app {

struct NameFields {
    std::string preset; ///< the preset's name, '/' → '-', no folder or .toml
    std::uint64_t seed = 0;
    std::string variant; ///< a manifest variant's name ("" outside batches)
};

class OutputNames {
public:
    /// @param where where the pattern came from, for messages ("presets/x.toml:3", "--name")
    /// @throws InputError for an unknown field, an empty name, or one that would leave the output
    ///         folder (absolute, "..", a backslash, a control character or NUL).
    OutputNames(std::string pattern, NameFields fields, std::string where);

    std::string base() const;
    std::filesystem::path map_file(const std::filesystem::path& dir, const io::EncodedMap& map) const;
    const NameFields& fields() const { return m_fields; }

private:
    std::string expand(const std::string& map) const;
    std::string m_pattern;
    NameFields m_fields;
    std::string m_where;
};

/// The preset's name as a file name: "bark/table-5-2-a" → "bark-table-5-2-a", "dir/x.toml" → "x".
std::string preset_file_name(const std::string& preset_name);

} // namespace crackle::app
