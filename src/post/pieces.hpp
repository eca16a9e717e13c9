#pragma once
/// @file Post-processing (Federl 2002, §4.5, Figs. 4.10–4.11; digest §2.5): every fragment of a
/// crack pattern becomes a solid piece of the local layer thickness. Walls between pieces are
/// glued at the bottom where cracked, so cracks open at the top; pieces relax under further
/// drying (extra shrinkage, solved with the wedge FEM, top free, bottom glued); in curl mode
/// cracked pieces detach and their rims lift.

#include "core/math.hpp"
#include "fracture/crack_pattern.hpp"
#include "post/crack_network.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace crackle::post {

/// The [post] preset section.
struct PostOptions {
    /// Rim lift of detached pieces at their cracked edges, in layer thicknesses (0 = glued).
    double curl = 0.0;
    /// How far in from the edge the curl reaches, in layer thicknesses.
    double curl_width = 3.0;
    /// Shrinkage after the pattern has formed, [top, bottom] (further drying or weathering):
    /// the tops pull away from the cracks, which open into V-shaped grooves.
    double shrink_top = 0.0, shrink_bottom = 0.0;
    /// Radius of the rounding of crack lips (m); 0 = sharp.
    double bevel = 0.0;
    bool operator==(const PostOptions&) const = default; ///< every field: the options test compares whole structs
};

/// A vertex of the piece mesh, with what baking (texture space) and export (world) need.
struct PieceVertex {
    Vec2 uv = Vec2::Zero();       ///< texture coordinates; may leave [0, 1) on pieces across a periodic border
    double height = 0;            ///< above the background (m)
    Vec3 normal = Vec3::UnitZ();  ///< unit normal in the texture frame (x along u, y along v, z up)
    Vec3 position = Vec3::Zero(); ///< world position at the final time (m)
    Vec3 world_normal = Vec3::UnitZ();
    int fragment = -1; ///< piece label; −1 on the crack floor
    float crack = 0;   ///< 0 on top surfaces, 1 on walls and the crack floor
    /// The height before curl and lip rounding (m): baking shapes lips and curl per pixel from
    /// the distance to the crack instead of per vertex (no triangular halos along cracks).
    double base_height = 0;
    float crack_time = 0;    ///< walls and floor: when the crack formed, 0 = first, 1 = last
    float crack_opening = 0; ///< walls and floor: the simulated opening (m; 0 if not simulated)
};

struct PieceMesh {
    std::vector<PieceVertex> vertices;
    /// Counter-clockwise seen from outside: (b − a) × (c − a) points where the corners' world
    /// normals point (tops, walls, ledges and floor alike).
    std::vector<std::array<std::uint32_t, 3>> triangles;
    /// The top edge of every crack wall (a crack lip), as vertex pairs: baking draws them as
    /// lines so that closed cracks (split elements that have not opened) still show.
    std::vector<std::array<std::uint32_t, 2>> lips;
    /// The crack network's chains in the final configuration: the bake shapes the grooves from
    /// them (smoothed into curves), so the relief does not show the element-scale polylines.
    std::vector<CrackChain> chains;
    mesh::SurfaceKind kind = mesh::SurfaceKind::Plane;
    bool periodic = true;
    /// Metres per unit of u and v in the reference tile (the sphere: at the equator).
    Vec2 tile_size = Vec2::Ones();
    double max_height = 0;   ///< the tallest point (m): the displacement map's full scale
    double element_size = 0; ///< mean top edge length (m): the scale of the simulation's facets
    double post_curl = 0, post_curl_width = 3.0, post_bevel = 0; ///< the PostOptions that shaped it
    int fragments = 0;
    std::size_t top_triangles = 0, wall_triangles = 0, floor_triangles = 0;
};

/// Builds the solid pieces of a crack pattern.
PieceMesh build_pieces(const fracture::CrackPattern& pattern, const PostOptions& options);

/// Reference texture coordinates of a surface point at t = 0 (u, v ∈ [0, 1)).
Vec2 reference_uv(const mesh::Surface& surface, const Vec3& p0);

} // namespace crackle::post
