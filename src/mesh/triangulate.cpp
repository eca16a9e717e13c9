#include "mesh/triangulate.hpp"

#include "core/error.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <sstream>

namespace crackle::mesh {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

struct CopyInfo {
    std::uint32_t index;
    std::int32_t ox, oy;
};
using Vb2 = CGAL::Triangulation_vertex_base_with_info_2<CopyInfo, K>;
using Tds2 = CGAL::Triangulation_data_structure_2<Vb2, CGAL::Triangulation_face_base_2<K>>;
using Delaunay2 = CGAL::Delaunay_triangulation_2<K, Tds2>;

using Vb3 = CGAL::Triangulation_vertex_base_with_info_3<std::uint32_t, K>;
using Tds3 = CGAL::Triangulation_data_structure_3<Vb3, CGAL::Delaunay_triangulation_cell_base_3<K>>;
using Delaunay3 = CGAL::Delaunay_triangulation_3<K, Tds3>;

constexpr double GRID_STEPS = 1073741824.0; // 2³⁰ grid steps across the domain width

/// One attempt with a given margin (in grid units). Returns false if some kept triangle's
/// circumcircle leaves the band of copies.
bool triangulate_with_margin(const std::vector<Vec2>& grid_pts, double nx, double ny, double margin,
                             std::vector<Face>& faces) {
    const int kx = static_cast<int>(std::ceil(margin / nx));
    const int ky = static_cast<int>(std::ceil(margin / ny));
    std::vector<std::pair<K::Point_2, CopyInfo>> input;
    input.reserve(grid_pts.size() * 2);
    for (int oy = -ky; oy <= ky; ++oy)
        for (int ox = -kx; ox <= kx; ++ox)
            for (std::size_t i = 0; i < grid_pts.size(); ++i) {
                const double x = grid_pts[i].x() + ox * nx; // exact: integers below 2⁵³
                const double y = grid_pts[i].y() + oy * ny;
                if (x < -margin || x > nx + margin || y < -margin || y > ny + margin) continue;
                input.push_back({K::Point_2(x, y), CopyInfo{static_cast<std::uint32_t>(i), ox, oy}});
            }
    Delaunay2 dt(input.begin(), input.end());
    CRACKLE_ASSERT(dt.number_of_vertices() == input.size(), "coincident points after snapping to the grid");

    faces.clear();
    faces.reserve(2 * grid_pts.size());
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
        const K::Point_2& a = f->vertex(0)->point();
        const K::Point_2& b = f->vertex(1)->point();
        const K::Point_2& c = f->vertex(2)->point();
        const double cx = (a.x() + b.x() + c.x()) / 3.0;
        const double cy = (a.y() + b.y() + c.y()) / 3.0;
        if (cx < 0 || cx >= nx || cy < 0 || cy >= ny) continue;
        // The circumcircle must lie inside the band, so no missing copy can be inside it.
        const K::Point_2 cc = CGAL::circumcenter(a, b, c);
        const double r = std::sqrt(CGAL::squared_distance(cc, a)) * (1.0 + 1e-9) + 1.0;
        if (cc.x() - r < -margin || cc.x() + r > nx + margin || cc.y() - r < -margin || cc.y() + r > ny + margin)
            return false;
        Face face;
        for (int k = 0; k < 3; ++k) {
            const CopyInfo& info = f->vertex(k)->info();
            face.v[static_cast<std::size_t>(k)] = vertex_id(info.index);
            face.offset[static_cast<std::size_t>(k)] = Vec2i(info.ox, info.oy);
        }
        faces.push_back(face);
    }
    return true;
}

/// Rotates each face so that its smallest vertex id comes first, then sorts the faces: the
/// mesh does not depend on CGAL's internal storage order.
void sort_faces(std::vector<Face>& faces) {
    for (Face& f : faces) {
        const auto m = static_cast<std::size_t>(std::min_element(f.v.begin(), f.v.end()) - f.v.begin());
        std::rotate(f.v.begin(), f.v.begin() + static_cast<long>(m), f.v.end());
        std::rotate(f.offset.begin(), f.offset.begin() + static_cast<long>(m), f.offset.end());
    }
    auto key = [](const Face& f) {
        auto id = [](VertexId v) { return static_cast<std::int64_t>(ix(v)); };
        return std::array<std::int64_t, 9>{id(f.v[0]),      id(f.v[1]),      id(f.v[2]),
                                           f.offset[0].x(), f.offset[0].y(), f.offset[1].x(),
                                           f.offset[1].y(), f.offset[2].x(), f.offset[2].y()};
    };
    std::sort(faces.begin(), faces.end(), [&](const Face& a, const Face& b) { return key(a) < key(b); });
}

} // namespace

SurfaceMesh triangulate_periodic(const std::vector<Vec2>& points, const Surface& surface) {
    CRACKLE_ASSERT(surface.periodic(), "triangulate_periodic needs a plane or cylinder");
    const Vec2 period = surface.period();
    const double g = period.x() / GRID_STEPS; // grid step (m)
    const double nx = GRID_STEPS;
    const double ny = std::round(period.y() / g);

    // === Snap to the integer grid (coordinates in grid units, exactly representable)
    std::vector<Vec2> grid_pts(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double x = std::floor(wrap(points[i].x(), period.x()) / g);
        const double y = std::floor(wrap(points[i].y(), period.y()) / g);
        grid_pts[i] = Vec2(std::min(x, nx - 1), std::min(y, ny - 1));
    }

    // === Triangulate the band of copies; widen the band until every circumcircle fits
    const double spacing = std::sqrt(nx * ny / static_cast<double>(std::max<std::size_t>(points.size(), 1)));
    double margin = 3.0 * spacing;
    std::vector<Face> faces;
    bool ok = false;
    for (int attempt = 0; attempt < 6 && !ok; ++attempt, margin *= 2.0)
        ok = triangulate_with_margin(grid_pts, nx, ny, margin, faces);
    if (!ok)
        throw NumericError("periodic Delaunay triangulation failed: too few points (" + std::to_string(points.size())
                           + ") for the domain; use more elements");

    sort_faces(faces);
    SurfaceMesh mesh;
    mesh.periodic = true;
    mesh.period = period;
    mesh.period_vectors = {surface.period_shift(Vec2i(1, 0)), surface.period_shift(Vec2i(0, 1))};
    for (const Vec2& gp : grid_pts) {
        const Vec2 d = gp * g;
        mesh.domain.push_back(d);
        mesh.positions.push_back(surface.position(d));
    }
    for (const Face& f : faces)
        mesh.faces.push_back(f);
    mesh.rebuild_adjacency();
    if (mesh.num_boundary_edges() != 0 || mesh.euler_characteristic() != 0) {
        std::ostringstream os;
        os << "periodic triangulation is not a closed torus (" << mesh.num_boundary_edges()
           << " open edges, Euler characteristic " << mesh.euler_characteristic() << ")";
        throw NumericError(os.str());
    }
    return mesh;
}

SurfaceMesh triangulate_sphere(const std::vector<Vec3>& points, const Surface& surface) {
    CRACKLE_ASSERT(surface.kind() == SurfaceKind::Sphere, "triangulate_sphere needs a sphere");
    std::vector<std::pair<K::Point_3, std::uint32_t>> input;
    input.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
        input.push_back({K::Point_3(points[i].x(), points[i].y(), points[i].z()), static_cast<std::uint32_t>(i)});
    Delaunay3 dt(input.begin(), input.end());
    CRACKLE_ASSERT(dt.dimension() == 3, "points on the sphere are degenerate (coplanar)");
    CRACKLE_ASSERT(dt.number_of_vertices() == points.size(), "coincident points on the sphere");

    SurfaceMesh mesh;
    mesh.periodic = false;
    for (const Vec3& p : points)
        mesh.positions.push_back(p);

    // The hull facets are the finite facets of the cells incident to the infinite vertex.
    std::vector<Delaunay3::Cell_handle> cells;
    dt.incident_cells(dt.infinite_vertex(), std::back_inserter(cells));
    std::vector<Face> faces;
    faces.reserve(cells.size());
    for (const auto& c : cells) {
        const int inf = c->index(dt.infinite_vertex());
        Face face;
        int k = 0;
        for (int j = 0; j < 4; ++j)
            if (j != inf) face.v[static_cast<std::size_t>(k++)] = vertex_id(c->vertex(j)->info());
        const Vec3& a = points[ix(face.v[0])];
        const Vec3& b = points[ix(face.v[1])];
        const Vec3& cpt = points[ix(face.v[2])];
        if ((b - a).cross(cpt - a).dot(a + b + cpt) < 0) std::swap(face.v[1], face.v[2]);
        faces.push_back(face);
    }
    sort_faces(faces);
    for (const Face& f : faces)
        mesh.faces.push_back(f);
    mesh.rebuild_adjacency();
    if (mesh.num_boundary_edges() != 0 || mesh.euler_characteristic() != 2)
        throw NumericError("sphere triangulation is not closed (Euler characteristic "
                           + std::to_string(mesh.euler_characteristic()) + ")");
    (void)surface;
    return mesh;
}

} // namespace crackle::mesh
