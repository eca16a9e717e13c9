#pragma once
/// @file Material shrinkage and the wedge's reference shape (Federl 2002, §3.3.2, Fig. 3.10;
/// digest §1.9–1.10). Shrinkage is negative isogonic growth of the material, applied to the
/// element's rest shape; the bottom nodes stay pinned to the background, and the mismatch is
/// what stresses the layer.

#include "core/math.hpp"

#include <array>

namespace crackle::sim {

/// Parameters from [material] shrinkage = [top, bottom]: linear shrinkage functions
/// s(t) = rate·t (digest §1.9 [R]); a negative rate means expansion.
struct ShrinkageOptions {
    double top_rate = 0.0;
    double bottom_rate = 0.0;

    double top(double t) const { return top_rate * t; }
    double bottom(double t) const { return bottom_rate * t; }
};

/// The 6 reference nodes of a wedge: bottom 0..2 (nodes 1–3 of the thesis), top 3..5 (nodes
/// 4–6), top node i+3 above bottom node i.
using WedgeNodes = std::array<Vec3, 6>;

/// Builds the reference shape (digest §1.10):
/// 1. scale the original bottom triangle about its centroid by (1 − s_top) → top face;
/// 2. scale it by (1 − s_bot) → bottom face;
/// 3. height h' = h·(1 − ½(s_top + s_bot));
/// 4. place the faces so that centroid_top − centroid_bot = h'·n;
/// with the bottom face's centroid kept at the original centroid.
/// @param bottom0  original bottom triangle (initial background positions), counter-clockwise about n
/// @param n        unit normal (the extrusion direction)
/// @param height   initial layer thickness h (m)
WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const Vec3& n, double height, double s_top,
                           double s_bot);

/// The same construction with a normal and a height per corner: top corner i sits at
/// h'_i·n_i above the scaled bottom corner. With the surface's vertex normals and the
/// vertex thickness, neighbouring elements agree on every shared top node's rest position,
/// so an unloaded layer on a curved or varying-thickness background is stress free (the
/// thesis' per-face normal leaves a misfit there: digest §1.10 [I] "On curved backgrounds").
/// With equal normals and heights it reduces to the thesis' form above.
WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const std::array<Vec3, 3>& normals,
                           const std::array<double, 3>& heights, double s_top, double s_bot);

} // namespace crackle::sim
