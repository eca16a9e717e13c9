#pragma once
/// @file Conforming refinement of a surface mesh: edge bisection and Rivara & Inostroza's
/// recursive longest-edge bisection (Federl 2002, §5.6.4, Alg. 9, Fig. 5.15). Every face is
/// only ever split along its own longest edge, which keeps the triangles well shaped.

#include "mesh/surface_mesh.hpp"

#include <functional>
#include <vector>

namespace crackle::mesh {

/// Where a new vertex goes when edge `edge` of face `f` is bisected: its canonical domain
/// coordinates (periodic meshes) and its 3D background position at t = 0.
struct NewVertex {
    Vec2 domain = Vec2::Zero();
    Vec3 position = Vec3::Zero();
};
using MidpointRule = std::function<NewVertex(const SurfaceMesh&, FaceId f, int edge)>;

/// What a bisection did.
struct EdgeSplit {
    VertexId vertex = NO_VERTEX;                     ///< the new vertex
    std::vector<std::pair<FaceId, FaceId>> children; ///< (kept id, new id) per split face
};

/// Bisects edge `edge` of `f` and the face across it (if any): f = (a, b, c) becomes
/// (a, m, c) and a new face (m, b, c); likewise the neighbour. Periodic offsets of the new
/// vertex are worked out in each face's own frame. Rebuilds the adjacency.
EdgeSplit split_edge(SurfaceMesh& mesh, FaceId f, int edge, const NewVertex& m);

/// Flips edge `edge` of face f (a, b, c) with its neighbour (b, a, d) into (a, d, c) and
/// (d, b, c), keeping each face's periodic frame; updates the adjacency. Returns the
/// neighbour, or NO_FACE (nothing done) on a border edge. The caller checks convexity.
FaceId flip_edge(SurfaceMesh& mesh, FaceId f, int edge);

/// Index of the longest edge of a face (3D corner positions; ties broken by vertex ids so
/// the choice is a strict order and the recursion terminates).
int longest_edge(const SurfaceMesh& mesh, FaceId f);

/// Rivara bisection of `f` (Alg. 9): neighbours whose longest edge is not the shared edge
/// are bisected first, recursively, so the mesh stays conforming. Appends every split to
/// `splits` in the order done.
void rivara_bisect(SurfaceMesh& mesh, FaceId f, const MidpointRule& midpoint, std::vector<EdgeSplit>& splits);

/// The usual midpoint rules: the middle of the edge in the unrolled domain mapped onto the
/// surface (plane, cylinder), or the chord midpoint projected onto the sphere.
MidpointRule domain_midpoint(const std::function<Vec3(const Vec2&)>& position_of_domain);
MidpointRule projected_midpoint(const std::function<Vec3(const Vec3&)>& project);

} // namespace crackle::mesh
