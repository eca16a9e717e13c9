#pragma once
/// @file Wavefront OBJ of a surface mesh (debug output of `crackle mesh --obj`).

#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <string>

namespace crackle::io {

/// OBJ text with positions, texture coordinates and normals. On periodic surfaces a face
/// across the border uses shifted copies of its vertices, so the unrolled tile is complete
/// and its border faces stick out by one triangle.
std::string surface_mesh_obj(const mesh::SurfaceMesh& mesh, const mesh::Surface& surface);

} // namespace crackle::io
