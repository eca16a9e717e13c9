#pragma once
/// @file The triangle mesh on a surface, with the adjacency later stages need to split
/// elements and walk crack tips.
///
/// Periodic surfaces (plane, cylinder) are tori: each face corner stores the lattice offset
/// of the copy of its vertex that the face uses, so a face across the border is an ordinary
/// face (no seam). The 3D corner position is `positions[v] + o.x·period_u + o.y·period_v`.
/// Faces are counter-clockwise seen from outside (normals point away from the background's
/// interior). Edge k of a face runs from corner k to corner (k + 1) mod 3.

#include "core/math.hpp"
#include "mesh/ids.hpp"

#include <array>
#include <string>
#include <vector>

namespace crackle::mesh {

struct Face {
    std::array<VertexId, 3> v;
    std::array<Vec2i, 3> offset = {Vec2i::Zero(), Vec2i::Zero(), Vec2i::Zero()};
};

/// Neighbour across one edge: the face and the index of the shared edge in it.
struct FaceNeighbor {
    FaceId face = NO_FACE;
    int edge = -1;
};

class SurfaceMesh {
public:
    // === Data
    IdVector<VertexId, Vec3> positions; ///< #V background positions at t = 0 (m)
    IdVector<VertexId, Vec2> domain;    ///< #V domain coordinates (periodic surfaces; else empty)
    IdVector<FaceId, Face> faces;       ///< #F
    bool periodic = false;
    Vec2 period = Vec2::Zero();                                        ///< domain period (Lx, Ly) of a periodic mesh
    std::array<Vec3, 2> period_vectors = {Vec3::Zero(), Vec3::Zero()}; ///< 3D shifts per unit offset

    std::size_t num_vertices() const { return positions.size(); }
    std::size_t num_faces() const { return faces.size(); }

    // === Geometry
    Vec3 corner_position(FaceId f, int k) const;
    /// to − from over the periodic images of `to` (t = 0 positions): the short way across a seam,
    /// where two neighbours' own positions lie a period apart. Plain to − from on other meshes.
    Vec3 nearest_step(const Vec3& from, const Vec3& to) const;
    std::array<Vec3, 3> face_positions(FaceId f) const;
    /// Unrolled domain coordinates of a corner (periodic meshes only).
    Vec2 corner_domain(FaceId f, int k) const;
    Vec3 face_normal(FaceId f) const; ///< unit, from the corner positions
    double face_area(FaceId f) const;
    std::array<double, 3> face_angles(FaceId f) const; ///< interior angles (rad) at corners 0..2
    double total_area() const;

    // === Adjacency
    /// Rebuilds neighbours and vertex→face links. Throws InvariantError on a non-manifold edge.
    void rebuild_adjacency();
    /// Updates the adjacency after local changes, in time proportional to them: `changed`
    /// lists every face whose corners changed and every face added since the last update.
    /// Vertices that lost all their faces keep a stale vertex→face link (nothing asks for it).
    void update_adjacency(const std::vector<FaceId>& changed);
    const FaceNeighbor& neighbor(FaceId f, int edge) const { return m_neighbors[f][edge]; }
    /// Faces around a vertex (one per incident corner; a face can repeat on tiny tori).
    std::vector<FaceId> vertex_faces(VertexId v) const;
    std::size_t num_edges() const { return m_num_edges; }
    std::size_t num_boundary_edges() const { return m_num_boundary_edges; }

    /// Euler characteristic V − E + F (torus 0, sphere 2).
    long euler_characteristic() const;

    /// Checks the invariants: valid ids, no degenerate face, every edge shared by at most two
    /// faces with opposite orientation and consistent periodic offsets, adjacency symmetric.
    /// Returns an empty string when valid, else a description of the first problem.
    std::string validate() const;

private:
    IdVector<FaceId, std::array<FaceNeighbor, 3>> m_neighbors;
    IdVector<VertexId, FaceId> m_vertex_face;
    std::size_t m_num_edges = 0;
    std::size_t m_num_boundary_edges = 0;
};

/// Mesh quality figures reported by `crackle mesh`.
struct MeshQuality {
    double min_angle_deg = 0;                                       ///< worst triangle's smallest angle
    double mean_min_angle_deg = 0;                                  ///< mean over triangles of their smallest angle
    double fraction_below_10deg = 0;                                ///< share of triangles with smallest angle < 10°
    double edge_min = 0, edge_mean = 0, edge_max = 0, edge_std = 0; ///< edge lengths (m)
};

MeshQuality mesh_quality(const SurfaceMesh& mesh);

} // namespace crackle::mesh
