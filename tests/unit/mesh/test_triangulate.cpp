#include "core/error.hpp"
#include "mesh/triangulate.hpp"
#include "support/accuracy.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;

namespace {

/// In-circle determinant of d against the counter-clockwise triangle (a, b, c); > 0 inside.
double incircle(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
    const Vec2 ad = a - d, bd = b - d, cd = c - d;
    return (ad.squaredNorm() * (bd.x() * cd.y() - cd.x() * bd.y())
            - bd.squaredNorm() * (ad.x() * cd.y() - cd.x() * ad.y())
            + cd.squaredNorm() * (ad.x() * bd.y() - bd.x() * ad.y()));
}

/// Counts edges that violate the local Delaunay condition, comparing each face with the far
/// vertex of its neighbour moved into the face's periodic frame; also counts seam edges.
std::pair<int, int> delaunay_violations(const mesh::SurfaceMesh& m) {
    int bad = 0, seam = 0;
    for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
        const auto f = mesh::face_id(fi);
        const Vec2 a = m.corner_domain(f, 0), b = m.corner_domain(f, 1), c = m.corner_domain(f, 2);
        const double scale = (b - a).squaredNorm() * (c - a).squaredNorm();
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = m.neighbor(f, k);
            const auto& F = m.faces[f];
            const auto& G = m.faces[nb.face];
            const auto ka = static_cast<std::size_t>(k);
            const auto ga = static_cast<std::size_t>((nb.edge + 1) % 3); // same vertex as corner k of f
            const Vec2i shift = F.offset[ka] - G.offset[ga];
            if (shift != Vec2i::Zero() || F.offset[ka] != Vec2i::Zero() || F.offset[(ka + 1) % 3] != Vec2i::Zero())
                ++seam;
            const Vec2 far =
                m.corner_domain(nb.face, (nb.edge + 2) % 3) + Vec2(shift.x() * m.period.x(), shift.y() * m.period.y());
            if (incircle(a, b, c, far) > 1e-9 * scale) ++bad;
        }
    }
    return {bad, seam};
}

} // namespace

TEST_SUITE("mesh") {
    TEST_CASE("triangulate: periodic meshes are closed tori that hold the Delaunay property across the seam") {
        int violations = 0, seams = 0;
        for (auto [w, h] : {std::pair{1.0, 1.0}, std::pair{2.0, 0.5}, std::pair{0.3, 1.7}}) {
            for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder}) {
                const mesh::Surface s = test::make_surface(kind, w, h);
                const mesh::SurfaceMesh m = test::make_mesh(s, 1200, 3);
                CAPTURE(w);
                CAPTURE(h);
                CHECK(m.validate() == "");
                CHECK(m.euler_characteristic() == 0);
                CHECK(m.num_boundary_edges() == 0);
                CHECK(m.num_faces() == 2 * m.num_vertices());
                const auto [bad, seam] = delaunay_violations(m);
                CHECK(bad == 0);
                CHECK(seam > 20); // the test really looked at edges across the border
                violations += bad;
                seams += seam;
                // The unrolled faces tile the domain exactly once.
                double area = 0;
                for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
                    const auto f = mesh::face_id(fi);
                    const Vec2 a = m.corner_domain(f, 0), b = m.corner_domain(f, 1), c = m.corner_domain(f, 2);
                    const double signed_area = 0.5 * ((b - a).x() * (c - a).y() - (c - a).x() * (b - a).y());
                    REQUIRE(signed_area > 0); // counter-clockwise in the domain
                    area += signed_area;
                }
                CHECK(area == doctest::Approx(w * h).epsilon(1e-9));
            }
        }
        test::record_claim("5.4", "periodic Delaunay correct across the seam (plane and cylinder, 6 domains)",
                           "face edges failing the in-circle test, 6 meshes (" + std::to_string(seams)
                               + " of them across the seam)",
                           violations, "= 0");
    }

    TEST_CASE("triangulate: face normals point outward on the cylinder") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Cylinder, 1.0, 0.5);
        const mesh::SurfaceMesh m = test::make_mesh(s, 800);
        for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
            const auto f = mesh::face_id(fi);
            const auto p = m.face_positions(f);
            const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
            REQUIRE(m.face_normal(f).dot(Vec3(c.x(), c.y(), 0).normalized()) > 0.9);
            for (const Vec3& q : p)
                REQUIRE(std::hypot(q.x(), q.y()) == doctest::Approx(s.radius()));
        }
    }

    TEST_CASE("triangulate: the sphere mesh is closed and outward and convex (Delaunay) with Euler characteristic 2") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Sphere, 1.5);
        const mesh::SurfaceMesh m = test::make_mesh(s, 2000, 7);
        CHECK(m.validate() == "");
        CHECK(m.euler_characteristic() == 2);
        CHECK(m.num_boundary_edges() == 0);
        CHECK(m.num_faces() == 2 * m.num_vertices() - 4);
        int concave = 0;
        for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
            const auto f = mesh::face_id(fi);
            const auto p = m.face_positions(f);
            const Vec3 n = m.face_normal(f);
            REQUIRE(n.dot(p[0] + p[1] + p[2]) > 0);
            // Empty circumsphere on a sphere ⇔ every neighbour's far vertex lies below the face plane.
            for (int k = 0; k < 3; ++k) {
                const mesh::FaceNeighbor nb = m.neighbor(f, k);
                const Vec3 far = m.corner_position(nb.face, (nb.edge + 2) % 3);
                concave += n.dot(far - p[0]) > 1e-12;
            }
        }
        CHECK(concave == 0);
        test::record_claim("5.4", "the convex hull gives the Delaunay triangulation of the sphere",
                           "edges failing the empty-circumsphere test (2000 points)", concave, "= 0");
        // Inscribed polyhedron: a little less area than the sphere.
        CHECK(m.total_area() < s.area());
        CHECK(m.total_area() > 0.99 * s.area());
    }

    TEST_CASE("triangulate: vertex fans close around every vertex of a torus") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        const mesh::SurfaceMesh m = test::make_mesh(s, 400);
        std::size_t corners = 0;
        for (std::size_t v = 0; v < m.num_vertices(); ++v) {
            const auto fan = m.vertex_faces(mesh::vertex_id(v));
            REQUIRE(fan.size() >= 3);
            corners += fan.size();
        }
        CHECK(corners == 3 * m.num_faces());
    }

    TEST_CASE("triangulate: three points on a periodic tile give a valid Delaunay torus of six triangles") {
        // Few points are not an error: the band of copies reaches 3 point spacings (here 1.7 tiles)
        // past the tile, so every circumcircle fits and the NumericError "too few points" is not
        // reached (nor with 0, 1 or 2 points). The result is the torus V − E + F = 0 with F = 2V
        // and E = 3V: 6 triangles, 9 edges, some using two copies of one vertex.
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        const std::vector<Vec2> pts = {Vec2(0.1, 0.1), Vec2(0.6, 0.2), Vec2(0.3, 0.7)};
        mesh::SurfaceMesh m;
        REQUIRE_NOTHROW(m = mesh::triangulate_periodic(pts, s));
        CHECK(m.validate() == "");
        CHECK(m.num_vertices() == 3);
        CHECK(m.num_faces() == 6);
        CHECK(m.num_edges() == 9);
        REQUIRE(m.num_boundary_edges() == 0); // delaunay_violations walks every edge's neighbour
        CHECK(m.euler_characteristic() == 0);
        for (std::size_t v = 0; v < 3; ++v)
            CHECK((m.domain[mesh::vertex_id(v)] - pts[v]).norm() < 1e-8); // snapped to the 2⁻³⁰ grid
        // The unrolled faces are counter-clockwise and tile the unit square exactly once.
        double area = 0;
        for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
            const auto f = mesh::face_id(fi);
            const Vec2 a = m.corner_domain(f, 0), b = m.corner_domain(f, 1), c = m.corner_domain(f, 2);
            const double signed_area = 0.5 * ((b - a).x() * (c - a).y() - (c - a).x() * (b - a).y());
            CHECK(signed_area > 0.05); // the smallest of these six is 0.11
            area += signed_area;
        }
        CHECK(std::abs(area - 1.0) < 1e-12);
        CHECK(delaunay_violations(m).first == 0);
    }
}
