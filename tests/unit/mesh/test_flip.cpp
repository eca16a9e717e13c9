#include "mesh/refine.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

using namespace crackle;

TEST_SUITE("mesh") {
    TEST_CASE("mesh: an edge flip keeps the mesh valid and the area, and flipping back restores the edge") {
        for (mesh::SurfaceKind kind : {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder}) {
            const mesh::Surface surface = test::make_surface(kind, 0.2, 0.2);
            mesh::SurfaceMesh m = test::make_mesh(surface, 300, 3);
            const double area = m.total_area();
            const long euler = m.euler_characteristic();
            const std::size_t edges = m.num_edges();
            int flipped = 0;
            for (std::size_t fi = 0; fi < m.num_faces(); fi += 7) {
                const mesh::FaceId f = mesh::face_id(fi);
                const auto a = m.faces[f].v[0], b = m.faces[f].v[1];
                const mesh::FaceId g = mesh::flip_edge(m, f, 0);
                REQUIRE(g != mesh::NO_FACE);
                CAPTURE(fi);
                REQUIRE(m.validate().empty());
                // The new diagonal joins the two far corners.
                CHECK(m.neighbor(f, 1).face == g);
                // f is now (a, d, c): its edge 1 (d → c) is the new diagonal; flipping it back
                // brings the old diagonal a–b back.
                const mesh::FaceId h = mesh::flip_edge(m, f, 1);
                REQUIRE(h == g);
                REQUIRE(m.validate().empty());
                bool has_ab = false;
                for (int k = 0; k < 3; ++k) {
                    const auto p = m.faces[f].v[static_cast<std::size_t>(k)];
                    const auto q = m.faces[f].v[static_cast<std::size_t>((k + 1) % 3)];
                    has_ab = has_ab || (p == b && q == a) || (p == a && q == b);
                }
                CHECK(has_ab);
                ++flipped;
            }
            CHECK(flipped > 10);
            CHECK(m.total_area() == doctest::Approx(area).epsilon(1e-12));
            CHECK(m.euler_characteristic() == euler);
            CHECK(m.num_edges() == edges);
        }
    }
}
