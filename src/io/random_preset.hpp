#pragma once
/// @file Random in-range presets for the soak test (issue 16, scripts/soak): every key of the
/// schema may be drawn, within its range, often at its bounds, so that a farm's variety of
/// legal inputs is tried before a farm tries it.

#include <cstdint>
#include <string>

namespace crackle::io {

struct RandomPresetOptions {
    double key_probability = 0.5;     ///< chance that a key is set (else its default)
    double bound_probability = 0.1;   ///< chance that a numeric key takes its min or max exactly
    std::int64_t min_elements = 500;  ///< simulation.elements is drawn from this range ...
    std::int64_t max_elements = 2000; ///< ... to keep a run small
    std::int64_t max_bake_size = 256; ///< bake.size and bake.size_v at most this
};

/// A whole preset as TOML (no `extends`; every key it leaves out takes its default). The same
/// seed gives the same text. Keys that name files (images, output names) and text lists (maps)
/// keep their defaults; everything else may be drawn.
std::string random_preset(std::uint64_t seed, const RandomPresetOptions& options = {});

} // namespace crackle::io
