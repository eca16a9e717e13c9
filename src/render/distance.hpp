#pragma once
/// @file Exact Euclidean distance transform of a pixel mask with the nearest source pixel
/// (Felzenszwalb & Huttenlocher 2012, "Distance transforms of sampled functions"), in metres:
/// pixels may be wider than tall (and on the sphere each row has its own width), and the image
/// wraps around u always and around v on periodic surfaces, so distances cross the tile's borders
/// the way the cracks do.

#include <cstdint>
#include <vector>

namespace crackle::render {

/// Pixel geometry of a map: `width` × `height`, row 0 at the top.
struct PixelGrid {
    int width = 0, height = 0;
    std::vector<double> metres_u; ///< per row: metres per pixel along u
    double metres_v = 1;          ///< metres per pixel along v
    bool wrap_v = true;           ///< periodic in v (plane, cylinder); u always wraps

    std::size_t pixels() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
    }
};

struct DistanceField {
    std::vector<float> distance;        ///< metres to the nearest source (∞ with no source)
    std::vector<std::uint32_t> nearest; ///< index of that source pixel (max without one; empty unless asked)
};

/// Distance from every pixel to the nearest pixel with source[i] != 0 (and, when asked, which).
DistanceField distance_transform(const PixelGrid& grid, const std::vector<std::uint8_t>& source,
                                 bool with_nearest = true);

} // namespace crackle::render
