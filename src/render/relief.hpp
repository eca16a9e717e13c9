#pragma once
/// @file The relief of the maps, shaped per pixel from the raster layers:
///  1. the simulated height smoothed within the plates (its linear triangles would otherwise
///     show as facets in the normal map);
///  2. crack lips rounded down into grooves whose reach and depth follow the nearest crack's
///     weight (its age and simulated opening: first cracks wide and deep, last ones fine),
///     measured with an exact distance transform (no triangular halos where a lip vertex dropped);
///  3. curled rims (post.curl) lifted by the same distance;
///  4. micro-relief: fibres, flakes and grit as tiling noise in metres.
/// Heights stay within [0, max]: the displacement's one documented range.

#include "render/crack_curves.hpp"
#include "render/detail.hpp"
#include "render/groove.hpp"
#include "render/raster.hpp"

#include <cstdint>
#include <vector>

namespace crackle::render {

struct ReliefOptions {
    double crack_width = 0; ///< m: how far the first cracks' lips round down into the plates
    double crack_depth = 0; ///< 0..1: share of the layer height the groove cuts down at the lip
    double crack_shape = 0; ///< 0 = V-shaped grooves (lips drop softly), 1 = rounded ridges (lips drop steeply)
    /// bake.grooves: false = grooves from the raster's crack pixels (the default), true = from
    /// the smoothed crack curves (render/groove.hpp; issue 35, in progress)
    bool curves = false;
    double wander = 0;               ///< m: crack curves' sub-element wander amplitude (bake.crack_wander)
    double wander_wavelength = 0;    ///< m: its wavelength (bake.crack_wander_wavelength; 0 = 4 elements)
    double tip_length = 0;           ///< m: grooves taper to a hairline over this length at tips (bake.tip_length)
    int shape_size = 2048;           ///< px across u the curve grooves' shapes are sized for (bake.shape_size)
    double bevel = 0;                ///< post.bevel (m): the least rounding of every lip
    double curl = 0, curl_width = 3; ///< post.curl, post.curl_width (layer thicknesses)
    double element_size = 0;         ///< m: the simulation's facet size (smoothing scale)
    DetailLayer fibre{0, 0.004, 8}, flake{0, 0.02, 1}, grit{0, 0.002, 1};
    std::uint32_t seed = 1;
    bool operator==(const ReliefOptions&) const = default; ///< every field: the options test compares whole structs
};

struct Relief {
    std::vector<float> height;   ///< m, in [0, max]
    std::vector<float> groove;   ///< 0 on plate tops, 1 in the crack: how far down into a groove
    std::vector<float> coverage; ///< share of the pixel's neighbourhood in a crack (a soft crack edge)
    std::vector<float> age;      ///< the nearest crack's age: 1 = the first crack, 0 = the last
    std::vector<float> detail;   ///< micro-relief, −1..1 (for shading)
    std::vector<float> flake;    ///< the flake's random number, 0..1 (for shading)
};

Relief shape_relief(const RasterLayers& layers, const ReliefOptions& options);

/// The relief with grooves cut along the smoothed crack curves (bake.grooves = "curves"):
///  1. the plates' height smoothed as above and continued across the cracks;
///  2. grooves from the distance to the curves (render/groove.hpp): a profile with continuous
///     normals whose reach and depth follow the crack's weight, tapering at tips;
///  3. curled rims lifted towards the cracks; 4. micro-relief as above. `coverage` is the
///  analytic share of a pixel inside a crack's floor or one-pixel hairline.
Relief shape_relief_curves(const RasterLayers& layers, const std::vector<CrackCurve>& curves,
                           const ReliefOptions& options);

/// The raster's crack flags, labels and ID colours made to agree with a curve relief's cracks:
/// a pixel is crack where the relief's coverage or groove is at least one half; a plate pixel
/// the raster had as crack takes the label (and ID colour) of the nearest plate pixel.
void relabel_cracks(RasterLayers& layers, const Relief& relief);

/// The grid at half resolution (2 × 2 blocks; both sides even), and a half-resolution map
/// upsampled bilinearly back onto `grid`.
PixelGrid half_grid(const PixelGrid& grid);
std::vector<float> upsample2(const PixelGrid& grid, const std::vector<float>& small);

/// A field on `coarse` (k times coarser than the map in each direction) at the map's pixels: cubic
/// (Catmull-Rom) interpolation between the coarse pixels' centres, wrapping in u (and in v where the
/// grid does; else the edge rows repeat). It passes through the coarse values and has continuous slopes.
std::vector<float> upsample_cubic(const PixelGrid& coarse, const std::vector<float>& field, int k);

/// A Gaussian-like blur (three box passes each way) of about `sigma_px` pixels; wraps in u,
/// and in v when grid.wrap_v.
std::vector<float> blur(const PixelGrid& grid, const std::vector<float>& values, double sigma_px);

/// Normalised convolution of `values` with a Gaussian-like kernel (three box passes each
/// way) of about `sigma_px` pixels, counting only pixels with mask[i] != 0; wraps in u, and in
/// v when grid.wrap_v. Pixels with no masked neighbour keep their value.
std::vector<float> masked_blur(const PixelGrid& grid, const std::vector<float>& values,
                               const std::vector<std::uint8_t>& mask, double sigma_px);

/// The plates' height (the raster's, on pixels that are not crack), ready to be smoothed: the
/// mean over 2 × 2 blocks when the smoothing is wide (σ ≥ 8 px on an even grid), else as is.
struct PlateHeights {
    PixelGrid grid; ///< the grid the values are on: the map's, or half of it
    bool half = false;
    std::vector<float> mean;
    std::vector<std::uint8_t> any; ///< 1 where a plate pixel contributed
};
PlateHeights plate_heights(const RasterLayers& layers, const std::vector<std::uint8_t>& plate, double sigma_px);

/// The plates' height blurred over `sigma_px` pixels of the map's grid `map`, without the
/// cracks pulling it down (masked_blur), back on the map's grid.
std::vector<float> smooth_plates(const PixelGrid& map, const PlateHeights& plates, double sigma_px);

} // namespace crackle::render
