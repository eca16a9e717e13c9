#pragma once
/// @file `simulation.elements = "auto"`: a model no finer than the scene needs. The element
/// count follows the crack spacing the layer's thickness implies (the speed-vs-accuracy study's
/// convergence table, docs/benchmarks.md "Model no more than a scene needs"), capped by what the
/// texture can show, and never below what a curved surface needs to stay valid.

#include "core/math.hpp"
#include "core/settings.hpp"

#include <cstdint>
#include <string>

namespace crackle::io {

/// The rule's constants, from the study (docs/benchmarks.md).
struct ResolutionRule {
    // The full model's elements per h² is a preset key, simulation.elements_per_h2 (2 by default,
    // 4 for mud: the study's cheapest density within the texture tolerance of the converged
    // answer for each; docs/benchmarks.md, "Model no more than a scene needs").
    /// The preview's (with fem-split's tip sub-model off): about a second for every shipped
    /// preset; mud's crack density and plate size come out 15 % and 40 % off the converged
    /// reference, its T share 0.2 low (docs/benchmarks.md).
    double preview_elements_per_thickness_squared = 0.3;
    /// Texture pixels per element at the cap: a triangle about 4 px on a side is the finest
    /// a crack path can show.
    double pixels_per_element = 8.0;
    std::int64_t min_elements = 400;
};

const ResolutionRule& resolution_rule();

struct ElementCount {
    std::int64_t elements = 0;
    bool automatic = false;
    std::string reason; ///< how an automatic count was reached (for the report and the log)
};

/// The surface's area (m²), from surface.kind and surface.size (not for a model: its own).
double surface_area(const Settings& s);

/// The fewest elements a curved surface needs (about six triangles around); 0 on the plane.
std::int64_t minimum_elements(const Settings& s);

/// A baked map's pixels.
struct MapSize {
    int width = 0;
    int height = 0;
    double pixels() const { return static_cast<double>(width) * static_cast<double>(height); }
};

/// The surface's texture tile in metres (u, v): the plane's and the cylinder's surface.size, the
/// sphere's 2πR × πR.
Vec2 texture_tile(const Settings& s);

/// The maps' pixels for bake.size and bake.size_v: bake.size is the longer side and the other
/// follows the texture tile (square texels), unless bake.size_v > 0 gives it. The one place a
/// map size is worked out (issue 29); `tile` is the preset's (texture_tile) or, for a pattern
/// loaded from a file, its pieces'.
MapSize map_size(const Settings& s, const Vec2& tile);
MapSize map_size(const Settings& s);

/// What bake.size and bake.size_v ask for, to be resolved against a tile later (MapSizeRequest::on).
struct MapSizeRequest {
    int size = 0; ///< bake.size: the longer side
    int rows = 0; ///< bake.size_v: the rows, 0 = follow the tile
    /// The maps' pixels on this tile (the rule of map_size).
    MapSize on(const Vec2& tile) const;
};
MapSizeRequest map_request(const Settings& s);

/// simulation.elements resolved: the number itself, or the auto rule for the map's pixels
/// (map_size). `preview` = the preview's coarser rule (applied to explicit counts too: min).
/// `model_area`: a model's area (m²), which its settings do not know (surface.kind = "mesh").
ElementCount element_count(const Settings& s, bool preview = false, double model_area = 0);

} // namespace crackle::io
