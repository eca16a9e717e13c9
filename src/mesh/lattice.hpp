#pragma once
/// @file Regular point lattices, the mass–spring model's "regular" discretization (Federl
/// 2002, §4.1: hexagonal cells, a triangular spring lattice with one spring family along u).

#include "core/math.hpp"

#include <vector>

namespace crackle::mesh {

/// A triangular lattice filling the torus [0, Lx) × [0, Ly) with about `count` points: rows
/// along u, an even number of them so the lattice closes across the border. The spacings
/// are stretched slightly (reported in `stretch` = y spacing / (x spacing·√3/2)) so whole
/// rows and columns fit the tile.
std::vector<Vec2> triangular_lattice(const Vec2& period, std::size_t count, double* stretch = nullptr);

/// Vertices of an icosahedron subdivided `level` times and projected onto a sphere: the most
/// regular triangulation of a sphere (10·4^level + 2 points; 12 of them have 5 neighbours).
std::vector<Vec3> icosphere_points(double radius, int level);

/// The subdivision level whose point count is nearest `count`.
int icosphere_level(std::size_t count);

} // namespace crackle::mesh
