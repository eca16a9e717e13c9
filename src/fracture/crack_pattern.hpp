#pragma once
/// @file The crack pattern: what every fracture method produces and every later stage
/// (statistics, post-processing, baking, export) consumes (design.md, stage 4).

#include "core/math.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <array>
#include <string>
#include <vector>

namespace crackle::fracture {

/// One side of a crack: an edge of an intact face whose other side is cracked (a removed
/// element, the other lip of a split, or the other Voronoi cell of a broken spring). The mesh is open along every crack
/// edge.
struct CrackEdge {
    mesh::FaceId face = mesh::NO_FACE; ///< the intact face the edge belongs to
    int edge = -1;                     ///< edge index in that face
    double opening = 0;                ///< crack width at the top surface, deformed (m)
    double depth = 0;                  ///< crack depth (m); the layer thickness for two-layer FEM
};

/// A fracture event, for temporal sequences (Fig. 5.30) and `--events`.
struct Event {
    double time = 0;
    Vec3 position = Vec3::Zero(); ///< reference (t = 0) position on the background
    std::string kind;             ///< "remove", "subdivide", "split", "break"
    double ratio = 0;             ///< stress / threshold that triggered it
};

struct CrackPattern {
    std::string method;
    mesh::Surface surface{mesh::SurfaceOptions{}};
    /// Top-surface topology; positions and domain are the reference (t = 0) background.
    mesh::SurfaceMesh mesh;
    std::vector<Vec3> deformed; ///< #V final top-node positions (canonical copies)
    std::array<Vec3, 2> deformed_period = {Vec3::Zero(), Vec3::Zero()}; ///< final period vectors
    std::vector<double> thickness;                                      ///< #V layer thickness (m)
    std::vector<double> young_modulus;                                  ///< #F Young's modulus per face (Pa)
    double poisson_ratio = 0.3;
    /// The background's affine growth map at the final time: bottom(t) = growth_map · P(0)
    /// (Eq. 3.4 with v = T·x: I + t·T).
    Mat3 growth_map = Mat3::Identity();
    std::vector<char> removed; ///< #F 1 where an element was removed (crack material)
    std::vector<int> fragment; ///< #F fragment label, −1 on removed faces
    int num_fragments = 0;
    std::vector<CrackEdge> cracks;
    std::vector<Event> events;
    double final_time = 0;
    std::size_t elements_initial = 0;
    bool events_capped = false; ///< the run stopped at the event limit before its duration

    /// Deformed 3D position of a face corner (periodic shift applied).
    Vec3 deformed_corner(mesh::FaceId f, int k) const;
};

/// The lips of an element-removal pattern: every edge of an intact face that faces a removed
/// face (or the mesh boundary), with face and edge set and opening and depth left zero.
std::vector<CrackEdge> removal_crack_lips(const CrackPattern& p);

/// Labels connected components of intact faces (linked across edges whose neighbour is
/// intact); fills `fragment` and `num_fragments`. Deterministic: labels follow face order.
void label_fragments(CrackPattern& pattern);

} // namespace crackle::fracture
