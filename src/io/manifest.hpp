#pragma once
/// @file Batch manifests (`crackle batch MANIFEST`, docs/farm.md): JSON Lines or TOML, one
/// variant per line or [[variant]] table, each with a preset, overrides, a seed and a name.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace crackle::io {

struct ManifestEntry {
    std::string preset;                 ///< built-in name or .toml path (relative to the manifest)
    std::vector<std::string> overrides; ///< "section.key=value", as --set takes them
    std::int64_t seed = -1;             ///< −1 = the preset's own
    std::string seeds;                  ///< a seed list ("1-10,20") to expand; "" = one variant
    std::string name;                   ///< output name pattern; "" = the batch's default
    std::string where;                  ///< "manifest.jsonl:12"
};

/// Reads every entry. Keys: preset (required), set (a table of key → value, or a list of
/// "key=value" texts), seed, seeds, name; anything else is refused so that a typo cannot go
/// unnoticed. Throws InputError with file:line.
std::vector<ManifestEntry> read_manifest_entries(const std::filesystem::path& path);

} // namespace crackle::io
