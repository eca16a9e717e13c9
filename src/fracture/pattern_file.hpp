#pragma once
/// @file The crack-pattern file (`crackle simulate --save X`, `bake --pattern X`, the pattern
/// cache): a CrackPattern with a JSON header saying what made it, so that baking and exporting
/// never re-run a simulation they already have.
///
/// Layout (little-endian, docs/farm.md "Pattern files"):
///   "CRACKLE-PATTERN\n" · u32 format version · u64 header length · header (JSON, UTF-8)
///   · body (the pattern's arrays, doubles bit-exact) · u64 FNV-1a checksum of everything before.
/// Doubles are stored bit for bit, so a bake from a loaded pattern is byte-identical to a bake
/// straight after the simulation. The loader checks every count and index against the file's
/// length and the mesh before it trusts it: a truncated, corrupt or foreign file is an
/// InputError, never a crash.

#include "core/json.hpp"
#include "fracture/crack_pattern.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace crackle::fracture {

/// The format version; bumped whenever the layout or the meaning of a field changes.
constexpr std::uint32_t PATTERN_FORMAT_VERSION = 1;

struct PatternFile {
    CrackPattern pattern;
    /// What made the pattern and what its report needs (the app's fields: crackle version,
    /// preset, seed, the simulation key, run counters).
    Json header = Json::object();
};

std::vector<std::uint8_t> encode_pattern(const CrackPattern& pattern, const Json& header);

/// @param source the file name for messages.
/// @throws InputError when the bytes are not a pattern file of this format version, are
///         truncated or corrupt, or describe an invalid mesh.
PatternFile decode_pattern(std::string_view bytes, const std::string& source);

/// Reads only the header (cheap: the cache checks keys with it).
Json pattern_header(std::string_view bytes, const std::string& source);

/// 64-bit FNV-1a of some bytes (checksums and cache keys).
std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed = 0xcbf29ce484222325ull);

} // namespace crackle::fracture
