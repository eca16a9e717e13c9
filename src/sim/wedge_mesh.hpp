#pragma once
/// @file Extrusion of the surface triangles into 6-node wedges of the local layer thickness
/// (Federl 2002, §5.2 step 3, Figs. 5.3 and 5.5).

#include "core/math.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/property_field.hpp"

#include <array>
#include <vector>

namespace crackle::sim {

/// Nodes 0..V−1 are the bottom (attachment) nodes, V..2V−1 the top nodes; top node V + i
/// sits above bottom node i along the surface normal. Wedge node k < 3 is face corner k at
/// the bottom, node k + 3 the same corner at the top; corner offsets are the face's.
struct WedgeMesh {
    std::vector<Vec3> nodes;                          ///< #2V node positions at t = 0 (m)
    std::vector<double> vertex_thickness;             ///< #V layer thickness per surface vertex (m)
    std::vector<std::array<std::uint32_t, 6>> wedges; ///< #F node ids
    std::size_t num_bottom = 0;

    /// Wedge volume from its 6 corner positions (bottom triangle area × mean height for
    /// prisms with parallel faces; exact for the straight extrusions made here).
    double wedge_volume(std::size_t w, const mesh::SurfaceMesh& mesh) const;
};

/// Extrudes every face; thickness is averaged per vertex over its incident faces
/// (each face's thickness is the field's average over its area, §5.9).
WedgeMesh extrude_wedges(const mesh::SurfaceMesh& mesh, const mesh::Surface& surface, const PropertyField& thickness);

} // namespace crackle::sim
