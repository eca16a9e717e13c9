#pragma once
/// @file Small meshes shared by the tests.

#include "core/rng.hpp"
#include "mesh/discretize.hpp"
#include "mesh/sampling.hpp"
#include "mesh/surface.hpp"
#include "mesh/triangulate.hpp"

namespace crackle::test {

inline mesh::Surface make_surface(mesh::SurfaceKind kind, double a = 1.0, double b = 1.0) {
    mesh::SurfaceOptions o;
    o.kind = kind;
    o.size = Vec2(a, b);
    return mesh::Surface(o);
}

/// Repelled points and their Delaunay triangulation with about `faces` triangles.
inline mesh::SurfaceMesh make_mesh(const mesh::Surface& surface, std::size_t faces, std::uint64_t seed = 1) {
    Rng rng(seed, RngStream::Sampling);
    mesh::DiscretizeOptions o;
    o.elements = faces;
    return mesh::discretize(surface, o, {}, rng);
}

} // namespace crackle::test
