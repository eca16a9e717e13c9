#pragma once
/// @file Delaunay triangulation (Federl 2002, §5.2.2) with CGAL. The only part of crackle
/// that includes CGAL (it takes ~12 s and ~1 GB to compile).

#include "core/math.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <vector>

namespace crackle::mesh {

/// Periodic Delaunay triangulation of points on the torus [0, Lx) × [0, Ly) of a plane or
/// cylinder. Every edge across the border is an ordinary edge (corner offsets, no seam).
///
/// CGAL 5.5's Periodic_2_Delaunay_triangulation_2 only accepts square domains, and
/// scaling a rectangle into a square would break the Delaunay (empty circle) property in
/// the real metric. So this triangulates the points plus their periodic copies within a
/// margin band with CGAL::Delaunay_triangulation_2, and keeps one representative of each
/// periodic triangle (the copy whose centroid lies in the fundamental domain). Every kept
/// triangle's circumcircle is checked to lie inside the band, which makes it a true
/// periodic Delaunay triangle; otherwise the band is widened. Coordinates are snapped to
/// an integer grid of Lx/2³⁰ first, so periodic copies are exact translations and CGAL's
/// exact predicates decide every copy identically.
/// Throws NumericError if no valid triangulation is found (fewer than ~10 points).
SurfaceMesh triangulate_periodic(const std::vector<Vec2>& points, const Surface& surface);

/// Delaunay triangulation of points on a sphere: their 3D convex hull (§5.2.2, Fig. 5.4),
/// taken from CGAL::Delaunay_triangulation_3. Faces are oriented outward.
SurfaceMesh triangulate_sphere(const std::vector<Vec3>& points, const Surface& surface);

} // namespace crackle::mesh
