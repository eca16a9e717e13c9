#pragma once
/// @file Micro-relief: fibres, flakes and grit as tiling noise in metres (render/noise.cpp).
/// A layer whose finest cells span many pixels is evaluated on a coarser grid and interpolated
/// (bilinear, wrapping), which keeps a 4096² bake's detail affordable.

#include "render/distance.hpp"

#include <cstdint>
#include <vector>

namespace crackle::render {

/// One tiling noise layer of micro-relief.
struct DetailLayer {
    double depth = 0;                                    ///< amplitude (m); 0 = off
    double size = 0.01;                                  ///< feature size (m) across u
    double stretch = 1;                                  ///< features this many times longer along v
    bool operator==(const DetailLayer&) const = default; ///< every field: the options test compares whole structs
};

struct DetailOptions {
    DetailLayer fibre{0, 0.004, 8}, flake{0, 0.02, 1}, grit{0, 0.002, 1};
    std::uint32_t seed = 1;
    double depth() const { return fibre.depth + flake.depth + grit.depth; }
};

struct Detail {
    std::vector<float> height; ///< m, within ±depth(); fading towards a sphere's poles
    std::vector<float> flake;  ///< the flake's random number, 0..1 (0.5 without flakes)
    int step = 1;              ///< the coarsest layer grid's spacing in pixels (1 = every pixel)
};

Detail micro_relief(const PixelGrid& grid, const DetailOptions& options);

} // namespace crackle::render
