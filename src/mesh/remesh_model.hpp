#pragma once
/// @file The simulation's mesh on the artist's model (issue 30; Federl 2002 §5.2 asks for
/// well-shaped elements of even size, which the thesis gets from repelled random points): CGAL's
/// isotropic remeshing to the element count asked for, borders kept, then each inner vertex
/// moved at random in its tangent plane and put back on the model, so that no two seeds share
/// a mesh and cracks have no lattice to follow.

#include "core/rng.hpp"
#include "mesh/model_surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <cstddef>

namespace crackle::mesh {

struct RemeshOptions {
    std::size_t elements = 8000; ///< about this many triangles
    int iterations = 5;          ///< of CGAL's split / collapse / flip / relax / project loop
    /// Random tangential move of each inner vertex, as a share of the target edge length.
    double jitter = 0.15;
};

/// Remeshes the model's surface. Throws InputError when its faces are wound inconsistently (CGAL
/// cannot hold them as one oriented surface).
SurfaceMesh remesh_model(const ModelSurface& surface, const RemeshOptions& options, Rng& rng);

/// The edge length of equilateral triangles that cover `area` with `elements` of them.
double target_edge_length(double area, std::size_t elements);

} // namespace crackle::mesh
