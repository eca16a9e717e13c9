#pragma once
/// @file What the steps of post::build_pieces pass between them: pieces.cpp makes the pieces'
/// vertices (steps 1-4), piece_triangles.cpp their triangles (step 5). Not for use outside post/.

#include "fracture/crack_pattern.hpp"
#include "post/crack_times.hpp"
#include "post/pieces.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace crackle::post::detail {

/// The pieces as a mesh of their own: every fragment gets its own copy of its vertices, so
/// the lips of a crack are separate boundary edges.
struct PieceTopology {
    mesh::SurfaceMesh mesh;
    std::vector<std::uint32_t> source_vertex; ///< piece vertex → pattern vertex
    std::vector<int> fragment;                ///< piece vertex → fragment
    std::vector<std::uint32_t> source_face;   ///< piece face → pattern face
};

/// A piece vertex at its final place: its top, and the foot of the wall under it.
struct Top {
    Vec2 uv; ///< canonical (before corner offsets)
    double height;
    double base; ///< before curl and lip rounding
    Vec3 world;  ///< canonical copy
    Vec3 bottom_world;
    Vec2 bottom_uv;
    double bottom_height;
};

/// u measured from `from`'s side of the sphere's date line (u wraps there; on periodic
/// surfaces the mesh already carries the shifts).
inline double unwrap_u(double u, double from, bool periodic) {
    if (periodic) return u;
    if (u - from > 0.5) return u - 1.0;
    if (u - from < -0.5) return u + 1.0;
    return u;
}

/// Metres per unit of u and v at a point of the reference surface.
inline Vec2 metric_at(const mesh::Surface& s, const Vec3& p0) {
    if (s.periodic()) return s.period();
    const double lat_cos = std::max(1e-3, std::sqrt(sqr(p0.x()) + sqr(p0.y())) / std::max(p0.norm(), 1e-300));
    return Vec2(TWO_PI * s.radius() * lat_cos, PI * s.radius());
}

/// Step 5: the tops (smooth normals per piece), a wall at every crack lip (a ledge where a crack
/// stops inside the layer) and the floor under removed elements, appended to `out`. Every
/// triangle is counter-clockwise seen from outside.
void add_triangles(const fracture::CrackPattern& p, const PieceTopology& topo, const std::vector<Top>& tops,
                   const std::vector<double>& thickness, const CrackTimes& times, PieceMesh& out);

} // namespace crackle::post::detail
