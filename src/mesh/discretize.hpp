#pragma once
/// @file The discretization stage (Federl 2002, §5.2): semi-random points on the
/// background surface, then their Delaunay triangulation.

#include "core/rng.hpp"
#include "core/timer.hpp"
#include "mesh/sampling.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <cstddef>
#include <functional>

namespace crackle::mesh {

struct DiscretizeOptions {
    std::size_t elements = 8000; ///< target triangle count
    SamplingOptions sampling;    ///< `count` is derived from `elements`
};

/// Local spacing scale over texture space (u, v) ∈ [0,1)²; density ∝ 1/s². Empty = uniform.
using SpacingOverUv = std::function<double(const Vec2& uv)>;

/// Number of points that gives `elements` triangles: F = 2V on a torus, F = 2V − 4 on a sphere.
std::size_t points_for_elements(SurfaceKind kind, std::size_t elements);

/// Samples and triangulates the surface (a model: remeshes it, mesh/remesh_model.hpp). Appends "sampling" and
/// "triangulation" wall times to `times` when given. Draws from `rng` (the Sampling stream).
SurfaceMesh discretize(const Surface& surface, const DiscretizeOptions& options, const SpacingOverUv& spacing, Rng& rng,
                       StepTimes* times = nullptr);

} // namespace crackle::mesh
