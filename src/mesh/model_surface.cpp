// Closest-point queries on the artist's model: CGAL's AABB tree over its triangles.
#include "mesh/model_surface.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

namespace crackle::mesh {

namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 point(const Vec3& p) {
    return {p.x(), p.y(), p.z()};
}
} // namespace

struct ModelSurface::Tree {
    Triangles triangles;
    AabbTree tree;
};

ModelSurface::ModelSurface(TriangleModel model) : m_model(std::move(model)), m_tree(std::make_unique<Tree>()) {
    m_vertex_normals.assign(m_model.positions.size(), Vec3::Zero());
    m_tree->triangles.reserve(m_model.triangles.size());
    for (const auto& t : m_model.triangles) {
        const Vec3& a = m_model.positions[static_cast<std::size_t>(t[0])];
        const Vec3& b = m_model.positions[static_cast<std::size_t>(t[1])];
        const Vec3& c = m_model.positions[static_cast<std::size_t>(t[2])];
        const Vec3 n = (b - a).cross(c - a); // |n| = twice the area: an area-weighted sum
        m_area += 0.5 * n.norm();
        for (int v : t)
            m_vertex_normals[static_cast<std::size_t>(v)] += n;
        m_tree->triangles.emplace_back(point(a), point(b), point(c));
    }
    for (Vec3& n : m_vertex_normals)
        if (n.norm() > 0) n.normalize();
    m_tree->tree.insert(m_tree->triangles.begin(), m_tree->triangles.end());
    m_tree->tree.build();
    m_tree->tree.accelerate_distance_queries();
}

ModelSurface::~ModelSurface() = default;

ModelSurface::Hit ModelSurface::closest(const Vec3& p) const {
    const auto [q, id] = m_tree->tree.closest_point_and_primitive(point(p));
    Hit hit;
    hit.triangle = static_cast<int>(id - m_tree->triangles.begin());
    hit.point = Vec3(q.x(), q.y(), q.z());
    hit.distance = (hit.point - p).norm();
    // Barycentric coordinates of the closest point in its triangle.
    const auto& t = m_model.triangles[static_cast<std::size_t>(hit.triangle)];
    const Vec3& a = m_model.positions[static_cast<std::size_t>(t[0])];
    const Vec3 e1 = m_model.positions[static_cast<std::size_t>(t[1])] - a;
    const Vec3 e2 = m_model.positions[static_cast<std::size_t>(t[2])] - a;
    const Vec3 d = hit.point - a;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
    const double u = det > 0 ? (d22 * e1.dot(d) - d12 * e2.dot(d)) / det : 0.0;
    const double v = det > 0 ? (d11 * e2.dot(d) - d12 * e1.dot(d)) / det : 0.0;
    hit.barycentric = Vec3(1.0 - u - v, u, v);
    return hit;
}

Vec3 ModelSurface::normal(const Hit& hit) const {
    const auto& t = m_model.triangles[static_cast<std::size_t>(hit.triangle)];
    Vec3 n = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
        n += hit.barycentric[k] * m_vertex_normals[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
    return n.norm() > 0 ? Vec3(n.normalized()) : n;
}

Vec2 ModelSurface::uv(const Hit& hit) const {
    if (!has_uv()) return Vec2::Zero();
    const auto& corners = m_model.corner_uv[static_cast<std::size_t>(hit.triangle)];
    return hit.barycentric[0] * corners[0] + hit.barycentric[1] * corners[1] + hit.barycentric[2] * corners[2];
}

} // namespace crackle::mesh
