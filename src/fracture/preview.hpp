#pragma once
/// @file A quick software rendering of a crack pattern in texture space (`simulate --png`):
/// fragments in flat colours, cracks dark. For looking at patterns, not a bake.

#include "fracture/crack_pattern.hpp"

#include <cstdint>
#include <vector>

namespace crackle::fracture {

struct RgbImage {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels; ///< RGB, row 0 at the top (v = 1)
};

/// Rasterizes the pattern's faces over texture space [0,1)², wrapping across periodic
/// borders (and the sphere's date line), `size` pixels per side.
RgbImage preview_image(const CrackPattern& pattern, int size);

} // namespace crackle::fracture
