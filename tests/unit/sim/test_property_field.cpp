#include "sim/property_field.hpp"
#include "sim/wedge_mesh.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;

namespace {
sim::VariationOptions noise(double scale, int octaves = 2) {
    sim::VariationOptions v;
    v.pattern = sim::PatternKind::Noise;
    v.amplitude = 0.5;
    v.scale = scale;
    v.octaves = octaves;
    return v;
}
} // namespace

TEST_SUITE("sim") {
    TEST_CASE("property field: noise tiles seamlessly on periodic surfaces and is smooth") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 0.6);
        const sim::SmoothNoise n(s, 0.1, 3, 42);
        Rng rng(1, RngStream::Test);
        double max_step = 0;
        for (int i = 0; i < 200; ++i) {
            const Vec2 uv(rng.uniform(), rng.uniform());
            const double g = n(Vec3::Zero(), uv);
            REQUIRE(g >= 0.0);
            REQUIRE(g <= 1.0);
            // Periodic: the same value one period over in u and in v.
            CHECK(n(Vec3::Zero(), uv + Vec2(1, 0)) == doctest::Approx(g).epsilon(1e-9));
            CHECK(n(Vec3::Zero(), uv + Vec2(0, -1)) == doctest::Approx(g).epsilon(1e-9));
            max_step = std::max(max_step, std::abs(n(Vec3::Zero(), uv + Vec2(1e-4, 0)) - g));
        }
        CHECK(max_step < 0.02); // continuous: tiny moves give tiny changes
    }

    TEST_CASE("property field: noise is deterministic in the seed and differs between seeds and has contrast") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Cylinder, 1.0, 1.0);
        const sim::SmoothNoise a(s, 0.1, 2, 7), b(s, 0.1, 2, 7), c(s, 0.1, 2, 8);
        double diff = 0, lo = 1, hi = 0;
        for (int i = 0; i < 100; ++i) {
            const Vec2 uv(0.01 * i, 0.37 * i);
            CHECK(a(Vec3::Zero(), uv) == b(Vec3::Zero(), uv));
            diff += std::abs(a(Vec3::Zero(), uv) - c(Vec3::Zero(), uv));
            lo = std::min(lo, a(Vec3::Zero(), uv));
            hi = std::max(hi, a(Vec3::Zero(), uv));
        }
        CHECK(diff > 1.0);
        CHECK(hi - lo > 0.3);
    }

    TEST_CASE("property field: p = p0(1 + a(2g - 1)) stays within its bounds and gradients are linear") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        sim::VariationOptions grad;
        grad.pattern = sim::PatternKind::Gradient;
        grad.amplitude = 0.5;
        grad.angle_deg = 0;
        const sim::PropertyField f(10.0, grad, s, 1, 1);
        CHECK(f.at(Vec3::Zero(), Vec2(0.0, 0.3)) == doctest::Approx(5.0));
        CHECK(f.at(Vec3::Zero(), Vec2(0.5, 0.9)) == doctest::Approx(10.0));
        CHECK(f.at(Vec3::Zero(), Vec2(1.0, 0.1)) == doctest::Approx(15.0));
        CHECK(f.min_value() == doctest::Approx(5.0));
        CHECK(f.max_value() == doctest::Approx(15.0));

        const sim::PropertyField nf(2.0, noise(0.05), s, 3, 2);
        Rng rng(2, RngStream::Test);
        for (int i = 0; i < 500; ++i) {
            const double v = nf.at(Vec3::Zero(), Vec2(rng.uniform(), rng.uniform()));
            REQUIRE(v >= 1.0 - 1e-12);
            REQUIRE(v <= 3.0 + 1e-12);
        }

        // A base that runs linearly along v: thickness = [start, end].
        const sim::PropertyField t(0.01, 0.04, sim::VariationOptions{}, s, 1, 1);
        CHECK(t.at(Vec3::Zero(), Vec2(0.3, 0.0)) == doctest::Approx(0.01));
        CHECK(t.at(Vec3::Zero(), Vec2(0.3, 0.5)) == doctest::Approx(0.025));
    }

    TEST_CASE("property field: an element takes the average of the image pixels inside it (§5.9)") {
        // Left half white, right half black.
        auto img = std::make_shared<GrayImage>();
        img->width = 64;
        img->height = 64;
        img->pixels.assign(64 * 64, 0.0f);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 32; ++x)
                img->at(x, y) = 1.0f;
        sim::VariationOptions v;
        v.pattern = sim::PatternKind::Image;
        v.amplitude = 0.5;
        v.image = img;
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        const sim::PropertyField f(100.0, v, s, 1, 1);
        const mesh::SurfaceMesh m = test::make_mesh(s, 400);
        int checked = 0;
        double total = 0, area = 0;
        for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
            const auto face = mesh::face_id(fi);
            const double avg = f.face_average(m, face, s);
            REQUIRE(avg >= 50.0 - 1e-9);
            REQUIRE(avg <= 150.0 + 1e-9);
            double umin = 1e9, umax = -1e9;
            for (int k = 0; k < 3; ++k) {
                const double u = wrap(m.corner_domain(face, k).x(), 1.0);
                umin = std::min(umin, u);
                umax = std::max(umax, u);
            }
            if (umax < 0.45 && umin > 0.05) { // fully inside the white half
                CHECK(avg == doctest::Approx(150.0).epsilon(1e-3));
                ++checked;
            }
            total += avg * m.face_area(face);
            area += m.face_area(face);
        }
        CHECK(checked > 50);
        // Over the whole surface: half at 150, half at 50.
        CHECK(total / area == doctest::Approx(100.0).epsilon(0.02));
    }

    TEST_CASE("wedges: extrusion by the local thickness with volumes adding up to area × thickness") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 0.5);
        const mesh::SurfaceMesh m = test::make_mesh(s, 300);
        const sim::PropertyField h(0.02, sim::VariationOptions{}, s, 1, 1);
        const sim::WedgeMesh w = sim::extrude_wedges(m, s, h);
        CHECK(w.nodes.size() == 2 * m.num_vertices());
        CHECK(w.wedges.size() == m.num_faces());
        double volume = 0;
        for (std::size_t i = 0; i < w.wedges.size(); ++i) {
            const double v = w.wedge_volume(i, m);
            REQUIRE(v > 0);
            volume += v;
        }
        CHECK(volume == doctest::Approx(0.5 * 0.02).epsilon(1e-9));
        for (std::size_t i = 0; i < m.num_vertices(); ++i)
            CHECK((w.nodes[m.num_vertices() + i] - w.nodes[i] - Vec3(0, 0, 0.02)).norm() < 1e-15);

        // On a sphere the top nodes sit radially outward by the thickness.
        const mesh::Surface sp = test::make_surface(SurfaceKind::Sphere, 1.0);
        const mesh::SurfaceMesh ms = test::make_mesh(sp, 300);
        const sim::WedgeMesh ws = sim::extrude_wedges(ms, sp, h);
        for (std::size_t i = 0; i < ms.num_vertices(); ++i)
            CHECK(ws.nodes[ms.num_vertices() + i].norm() == doctest::Approx(1.02));
    }
}
