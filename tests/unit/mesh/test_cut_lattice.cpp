#include "mesh/cut.hpp"
#include "mesh/lattice.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

#include <map>

using namespace crackle;

namespace {

std::vector<int> vertex_degrees(const mesh::SurfaceMesh& m) {
    std::vector<int> deg(m.num_vertices(), 0);
    for (const auto& f : m.faces)
        for (auto v : f.v)
            ++deg[mesh::ix(v)];
    return deg; // faces around a vertex = its edges on a closed mesh
}

/// Connected components of faces through shared edges.
int face_components(const mesh::SurfaceMesh& m) {
    std::vector<int> label(m.num_faces(), -1);
    int n = 0;
    for (std::size_t s = 0; s < m.num_faces(); ++s) {
        if (label[s] >= 0) continue;
        std::vector<std::size_t> stack{s};
        label[s] = n;
        while (!stack.empty()) {
            const std::size_t f = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                const auto nb = m.neighbor(mesh::face_id(f), k);
                if (nb.face == mesh::NO_FACE || label[mesh::ix(nb.face)] >= 0) continue;
                label[mesh::ix(nb.face)] = n;
                stack.push_back(mesh::ix(nb.face));
            }
        }
        ++n;
    }
    return n;
}

int open_edges(const mesh::SurfaceMesh& m) {
    int n = 0;
    for (std::size_t f = 0; f < m.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            n += m.neighbor(mesh::face_id(f), k).face == mesh::NO_FACE;
    return n;
}

Vec2 centroid_uv(const mesh::SurfaceMesh& m, std::size_t f) {
    const auto id = mesh::face_id(f);
    const Vec2 c = (m.corner_domain(id, 0) + m.corner_domain(id, 1) + m.corner_domain(id, 2)) / 3.0;
    return Vec2(wrap(c.x(), m.period.x()), wrap(c.y(), m.period.y()));
}

} // namespace

TEST_SUITE("mesh") {
    TEST_CASE("lattice: a periodic triangular lattice has six equal neighbours everywhere") {
        const auto surface = test::make_surface(mesh::SurfaceKind::Plane, 1.0, 1.0);
        double stretch = 0;
        const auto pts = mesh::triangular_lattice(surface.period(), 500, &stretch);
        CHECK(pts.size() == doctest::Approx(500).epsilon(0.15));
        CHECK(std::abs(stretch - 1.0) < 0.05);
        const mesh::SurfaceMesh m = mesh::triangulate_periodic(pts, surface);
        for (int d : vertex_degrees(m))
            CHECK(d == 6);
        // Edge lengths: the row spacing and the two diagonals, within the stretch.
        double lo = 1e9, hi = 0;
        for (std::size_t f = 0; f < m.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const double l =
                    (m.corner_domain(mesh::face_id(f), (k + 1) % 3) - m.corner_domain(mesh::face_id(f), k)).norm();
                lo = std::min(lo, l);
                hi = std::max(hi, l);
            }
        CHECK(hi / lo < 1.0 + std::abs(stretch - 1.0) + 1e-9);
    }

    TEST_CASE("lattice: an icosphere has 10·4^level + 2 points on the sphere and twelve of degree five") {
        for (int level = 1; level <= 3; ++level) {
            const auto pts = mesh::icosphere_points(2.0, level);
            CHECK(pts.size() == 10u * (1u << (2 * level)) + 2u);
            for (const Vec3& p : pts)
                CHECK(p.norm() == doctest::Approx(2.0).epsilon(1e-12));
        }
        CHECK(mesh::icosphere_level(642) == 3);
        CHECK(mesh::icosphere_level(700) == 3);
        const auto surface = test::make_surface(mesh::SurfaceKind::Sphere, 1.0, 1.0);
        const mesh::SurfaceMesh m = mesh::triangulate_sphere(mesh::icosphere_points(surface.radius(), 2), surface);
        std::map<int, int> count;
        for (int d : vertex_degrees(m))
            ++count[d];
        CHECK(count[5] == 12);
        CHECK(count[6] == static_cast<int>(m.num_vertices()) - 12);
    }

    TEST_CASE("cut: a closed loop of cut edges separates the mesh and a single cut edge stays a closed slit") {
        const auto surface = test::make_surface(mesh::SurfaceKind::Plane, 1.0, 1.0);
        const mesh::SurfaceMesh base = test::make_mesh(surface, 800, 5);
        REQUIRE(face_components(base) == 1);
        REQUIRE(open_edges(base) == 0);

        // The border of a disk of faces.
        mesh::SurfaceMesh m = base;
        auto inside = [&](std::size_t f) { return (centroid_uv(m, f) - Vec2(0.5, 0.5)).norm() < 0.2; };
        std::vector<std::array<char, 3>> cut(m.num_faces(), {0, 0, 0});
        int marked = 0;
        for (std::size_t f = 0; f < m.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const auto nb = m.neighbor(mesh::face_id(f), k);
                if (inside(f) != inside(mesh::ix(nb.face))) {
                    cut[f][static_cast<std::size_t>(k)] = 1;
                    ++marked;
                }
            }
        const auto origin = mesh::cut_along(m, cut);
        CHECK(face_components(m) == 2);
        CHECK(open_edges(m) == marked);
        // Every loop vertex got one copy, at the same place.
        CHECK(m.num_vertices() == base.num_vertices() + static_cast<std::size_t>(marked / 2));
        REQUIRE(origin.size() == m.num_vertices());
        for (std::size_t v = 0; v < m.num_vertices(); ++v)
            CHECK(m.domain[mesh::vertex_id(v)] == base.domain[origin[v]]);

        // One interior edge: both ends are crack tips, nothing can open.
        mesh::SurfaceMesh slit = base;
        std::vector<std::array<char, 3>> one(slit.num_faces(), {0, 0, 0});
        const auto nb = slit.neighbor(mesh::face_id(0), 0);
        one[0][0] = 1;
        one[mesh::ix(nb.face)][static_cast<std::size_t>(nb.edge)] = 1;
        mesh::cut_along(slit, one);
        CHECK(slit.num_vertices() == base.num_vertices());
        CHECK(open_edges(slit) == 0);

        // Two edges in a row: the middle vertex splits and both edges open.
        mesh::SurfaceMesh two = base;
        std::vector<std::array<char, 3>> path(two.num_faces(), {0, 0, 0});
        const auto n0 = two.neighbor(mesh::face_id(0), 0), n1 = two.neighbor(mesh::face_id(0), 1);
        path[0][0] = path[0][1] = 1;
        path[mesh::ix(n0.face)][static_cast<std::size_t>(n0.edge)] = 1;
        path[mesh::ix(n1.face)][static_cast<std::size_t>(n1.edge)] = 1;
        mesh::cut_along(two, path);
        CHECK(two.num_vertices() == base.num_vertices() + 1);
        CHECK(open_edges(two) == 4);
        CHECK(face_components(two) == 1);
    }
}
