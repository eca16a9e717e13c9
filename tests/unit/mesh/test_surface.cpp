#include "mesh/surface.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;

TEST_SUITE("mesh") {
    TEST_CASE("surface: tangent frames are orthonormal and right-handed with an outward normal") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            const mesh::Surface s = test::make_surface(kind, 0.7, 0.4);
            Rng rng(5, RngStream::Test);
            for (int i = 0; i < 50; ++i) {
                Vec3 p;
                if (s.periodic())
                    p = s.position(Vec2(rng.uniform() * s.period().x(), rng.uniform() * s.period().y()));
                else
                    p = s.project(Vec3(rng.normal(), rng.normal(), rng.normal()));
                const mesh::TangentFrame f = s.frame(p);
                CAPTURE(mesh::to_string(kind));
                CHECK(f.e_u.norm() == doctest::Approx(1.0));
                CHECK(f.e_v.norm() == doctest::Approx(1.0));
                CHECK(f.n.norm() == doctest::Approx(1.0));
                CHECK(std::abs(f.e_u.dot(f.e_v)) < 1e-12);
                CHECK(std::abs(f.e_u.dot(f.n)) < 1e-12);
                CHECK(f.e_u.cross(f.e_v).dot(f.n) == doctest::Approx(1.0));
                if (kind != SurfaceKind::Plane)
                    CHECK(f.n.dot(Vec3(p.x(), p.y(), kind == SurfaceKind::Sphere ? p.z() : 0.0)) > 0);
            }
        }
    }

    TEST_CASE("surface: texture coordinates lie in the unit square and follow the parameterization") {
        const mesh::Surface cyl = test::make_surface(SurfaceKind::Cylinder, 2.0, 3.0);
        CHECK(cyl.radius() == doctest::Approx(2.0 / (2 * PI)));
        // A quarter of the way around and a third of the way up.
        const Vec2 uv = cyl.uv(cyl.position(Vec2(0.5, 1.0)));
        CHECK(uv.x() == doctest::Approx(0.25));
        CHECK(uv.y() == doctest::Approx(1.0 / 3.0));
        // Moving along e_u increases u: the frame matches the parameterization.
        const Vec3 p = cyl.position(Vec2(0.3, 1.0));
        const Vec2 uv2 = cyl.uv(p + 1e-6 * cyl.frame(p).e_u);
        CHECK(uv2.x() > cyl.uv(p).x());

        const mesh::Surface sphere = test::make_surface(SurfaceKind::Sphere, 2.0);
        CHECK(sphere.uv(Vec3(0, 0, 2)).y() == doctest::Approx(1.0));
        CHECK(sphere.uv(Vec3(0, 0, -2)).y() == doctest::Approx(0.0));
        CHECK(sphere.uv(Vec3(2, 0, 0)).y() == doctest::Approx(0.5));
        CHECK(sphere.uv(Vec3(0, 2, 0)).x() == doctest::Approx(0.25));
        const Vec3 q = sphere.project(Vec3(1, 1, 1));
        CHECK(q.norm() == doctest::Approx(2.0));
        CHECK(sphere.uv(q + 1e-6 * sphere.frame(q).e_v).y() > sphere.uv(q).y());
        CHECK(sphere.area() == doctest::Approx(4 * PI * 4));
    }

    TEST_CASE("surface: periodic shifts identify the copies across the borders") {
        const mesh::Surface plane = test::make_surface(SurfaceKind::Plane, 2.0, 3.0);
        CHECK((plane.period_shift(Vec2i(1, -1)) - Vec3(2, -3, 0)).norm() == 0.0);
        const mesh::Surface cyl = test::make_surface(SurfaceKind::Cylinder, 2.0, 3.0);
        // Around the trunk the embedding wraps by itself: x + C maps to the same point.
        CHECK((cyl.position(Vec2(0.2, 0.5)) - cyl.position(Vec2(2.2, 0.5))).norm() < 1e-12);
        CHECK((cyl.period_shift(Vec2i(1, 1)) - Vec3(0, 0, 3)).norm() == 0.0);
    }
}
