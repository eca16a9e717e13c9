// Crack edges split at hanging nodes on one side only (fem-split's refinement next to a tip,
// thesis §5.6.2): the search that finds them, and the junction statistics that must not count
// the triangle they make as two junctions (checked on a hand-built pattern whose answer is known).

#include "fracture/hanging_splits.hpp"
#include "fracture/statistics.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace crackle;
using fracture::NodePair;

TEST_SUITE("fracture") {
    TEST_CASE(
        "hanging splits: a path through nodes on the coarse segment is found, in order, and a node off it is not") {
        // 0 — 1 — 2 — 3 along x (the finer side) and 0 — 3 (the coarse side); 4 off the segment.
        const std::vector<Vec3> at = {{0, 0, 0}, {0.25, 0.001, 0}, {0.6, -0.001, 0}, {1, 0, 0}, {0.5, 0.3, 0}};
        const std::vector<NodePair> single = {{0, 1}, {0, 3}, {1, 2}, {2, 3}};
        const auto splits = fracture::hanging_splits(single, at, Vec2::Zero());
        REQUIRE(splits.size() == 1);
        CHECK(splits[0].coarse == NodePair{0, 3});
        CHECK(splits[0].path == std::vector<std::uint32_t>{0, 1, 2, 3});
        CHECK(splits[0].t[1] == doctest::Approx(0.25));
        CHECK(splits[0].t[2] == doctest::Approx(0.6));
        // Three cracks meeting in a real triangle (node 4 is 0.3 off the segment 0 — 3): no split.
        CHECK(fracture::hanging_splits({{0, 3}, {0, 4}, {3, 4}}, at, Vec2::Zero()).empty());
        // A node 3 % of the segment's length off it is another crack, not a hanging node.
        const std::vector<Vec3> off = {{0, 0, 0}, {0.5, 0.03, 0}, {1, 0, 0}};
        CHECK(fracture::hanging_splits({{0, 1}, {0, 2}, {1, 2}}, off, Vec2::Zero()).empty());
    }

    TEST_CASE("hanging splits: across a periodic border the nearest image is used") {
        // On a unit torus: 0 at x = 0.95 and 2 at x = 0.05 are 0.1 apart through the border; the
        // hanging node 1 sits on the border (x = 0). Without the period the 0.95 m link 0 — 1
        // would be the coarse side instead (2 lies on it), the wrong crack.
        const std::vector<Vec3> at = {{0.95, 0.5, 0}, {0.0, 0.5, 0}, {0.05, 0.5, 0}};
        const std::vector<NodePair> single = {{0, 1}, {0, 2}, {1, 2}};
        const auto splits = fracture::hanging_splits(single, at, Vec2(1, 1));
        REQUIRE(splits.size() == 1);
        CHECK(splits[0].coarse == NodePair{0, 2});
        CHECK(splits[0].path == std::vector<std::uint32_t>{0, 1, 2});
        CHECK(splits[0].t[1] == doctest::Approx(0.5));
        const auto unwrapped = fracture::hanging_splits(single, at, Vec2::Zero());
        REQUIRE(unwrapped.size() == 1);
        CHECK(unwrapped[0].coarse == NodePair{0, 1});
    }

    TEST_CASE("hanging splits: on a sphere (3D positions), a hanging node on the surface is on the coarse chord") {
        // Edges a tenth of the radius long on the unit sphere: the hanging node m (the edge's
        // midpoint moved onto the sphere) sits L²/(8R) = 1.25 % of L off the chord, within the
        // 2 % the search allows; a node a quarter of L off it is a different crack.
        const Vec3 a = Vec3(1, 0, 0), b = Vec3(std::cos(0.1), std::sin(0.1), 0);
        const Vec3 m = (0.5 * (a + b)).normalized();
        const Vec3 off = (0.5 * (a + b) + 0.25 * (b - a).norm() * Vec3(0, 0, 1)).normalized();
        const std::vector<Vec3> at = {a, m, b, off};
        const auto splits = fracture::hanging_splits({{0, 1}, {0, 2}, {1, 2}}, at, Vec2::Zero());
        REQUIRE(splits.size() == 1);
        CHECK(splits[0].coarse == NodePair{0, 2});
        CHECK(splits[0].t[1] == doctest::Approx(0.5));
        CHECK(fracture::hanging_splits({{0, 3}, {0, 2}, {2, 3}}, at, Vec2::Zero()).empty());
    }

    TEST_CASE("pattern statistics: a crack split at a hanging node on one side has no junction there, and a real "
              "branch at that node is one T") {
        // A straight crack a₀ → b₀ along y = 2 on a 4 m periodic plane; above it the edge a → b is
        // one element edge, below it two (a → m → b, m a hanging node). Both lips of every edge.
        fracture::CrackPattern p;
        p.surface = test::make_surface(mesh::SurfaceKind::Plane, 4.0, 4.0);
        p.mesh.periodic = true;
        p.mesh.period = Vec2(4, 4);
        auto vertex = [&](double x, double y) {
            p.mesh.positions.push_back(Vec3(x, y, 0));
            p.mesh.domain.push_back(Vec2(x, y));
            return mesh::vertex_id(p.mesh.num_vertices() - 1);
        };
        const auto a0 = vertex(0.5, 2), a = vertex(1, 2), m = vertex(1.5, 2), b = vertex(2, 2), b0 = vertex(2.5, 2);
        const auto t0 = vertex(0.75, 2.5), t1 = vertex(1.5, 2.6), t2 = vertex(2.25, 2.5);
        const auto s0 = vertex(0.75, 1.5), s1 = vertex(1.25, 1.6), s2 = vertex(1.75, 1.6), s3 = vertex(2.25, 1.5);
        auto crack_face = [&](mesh::VertexId u, mesh::VertexId v, mesh::VertexId w) {
            p.mesh.faces.push_back(mesh::Face{{u, v, w}});
            p.cracks.push_back({mesh::face_id(p.mesh.num_faces() - 1), 0});
        };
        crack_face(a0, a, t0); // above: a₀ → a, a → b, b → b₀
        crack_face(a, b, t1);
        crack_face(b, b0, t2);
        crack_face(a, a0, s0); // below: a → a₀, m → a, b → m, b₀ → b
        crack_face(m, a, s1);
        crack_face(b, m, s2);
        crack_face(b0, b, s3);
        auto finish = [&] {
            p.removed.assign(p.mesh.num_faces(), 0);
            p.fragment.assign(p.mesh.num_faces(), 0);
            p.num_fragments = 1;
            return fracture::pattern_statistics(p);
        };
        const auto straight = finish();
        CHECK(straight.crack_length == doctest::Approx(2.0)); // each lip counts ½
        CHECK(straight.junctions == 0);                       // the coarse link would make a and b junctions
        CHECK(fracture::crack_path_statistics(p).chains == 1);

        // A branch from m straight down, 1 m: the one junction, a T (180°, 90°, 90°).
        const auto d = vertex(1.5, 1.0), l = vertex(1.2, 1.2), r = vertex(1.8, 1.2);
        crack_face(d, m, l);
        crack_face(m, d, r);
        const auto branched = finish();
        CHECK(branched.crack_length == doctest::Approx(3.0));
        CHECK(branched.junctions == 1);
        CHECK(branched.t_junction_fraction == 1.0);
        CHECK(fracture::crack_path_statistics(p).chains == 3);
    }
}
