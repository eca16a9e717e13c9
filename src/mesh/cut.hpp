#pragma once
/// @file Cutting a surface mesh along marked edges: vertices on a cut are duplicated so that
/// the faces on either side no longer share the edge, which becomes a boundary (a crack's two
/// lips). A cut that ends inside the mesh keeps its end vertex shared (a crack tip).

#include "mesh/surface_mesh.hpp"

#include <functional>
#include <vector>

namespace crackle::mesh {

/// `cut[f][k]` marks edge k of face f; both sides of an edge must be marked alike.
/// Returns, for every vertex of the result, the vertex it was copied from.
std::vector<VertexId> cut_along(SurfaceMesh& mesh, const std::vector<std::array<char, 3>>& cut);

/// The same cut, in time proportional to it: `edges` lists one side (face, edge) of each cut
/// edge, `faces_at(v)` the faces around a vertex (a superset is fine). Returns (copy, origin)
/// for each new vertex.
std::vector<std::pair<VertexId, VertexId>>
cut_edges(SurfaceMesh& mesh, const std::vector<std::pair<FaceId, int>>& edges,
          const std::function<const std::vector<std::uint32_t>&(VertexId)>& faces_at);

} // namespace crackle::mesh
