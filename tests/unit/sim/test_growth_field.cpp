#include "core/rng.hpp"
#include "sim/growth_field.hpp"
#include "support/accuracy.hpp"
#include "support/finite_diff.hpp"

#include <Eigen/Eigenvalues>
#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;
using sim::GrowthField;
using sim::GrowthKind;
using sim::GrowthOptions;

namespace {
GrowthOptions opts(GrowthKind kind, double r1, double r2, double angle) {
    GrowthOptions o;
    o.kind = kind;
    o.r1 = r1;
    o.r2 = r2;
    o.angle_deg = angle;
    return o;
}
} // namespace

TEST_SUITE("sim") {
    TEST_CASE("growth: every field's tensor equals the numerical Jacobian of its velocity (Eq. 3.3)") {
        struct Case {
            SurfaceKind surface;
            GrowthOptions options;
        };
        const Case cases[] = {
            {SurfaceKind::Plane, opts(GrowthKind::Isogonic, 0.7, 0.0, 0)},
            {SurfaceKind::Plane, opts(GrowthKind::Anisotropic, 1.0, 0.0, 90)}, // Fig. 3.6 vertical
            {SurfaceKind::Plane, opts(GrowthKind::Anisotropic, 1.0, 0.0, 0)},  // horizontal
            {SurfaceKind::Plane, opts(GrowthKind::Anisotropic, 1.0, 0.0, 45)}, // diagonal
            {SurfaceKind::Plane, opts(GrowthKind::Anisotropic, 1.0, 0.2, 0)},  // 5× faster horizontally
            {SurfaceKind::Plane, opts(GrowthKind::Anisotropic, 1.0, 0.2, -30)},
            {SurfaceKind::Cylinder, opts(GrowthKind::Anisotropic, 1.0, 0.0, 0)}, // Eq. 3.5 trunk
            {SurfaceKind::Cylinder, opts(GrowthKind::Anisotropic, 0.5, 0.3, 90)},
            {SurfaceKind::Cylinder, opts(GrowthKind::Isogonic, 0.4, 0.0, 0)},
            {SurfaceKind::Sphere, opts(GrowthKind::Isogonic, 1.0, 0.0, 0)},
            {SurfaceKind::Sphere, opts(GrowthKind::Anisotropic, 1.0, 4.0, 0)}, // Fig. 5.32: 4× along z
            {SurfaceKind::Plane, opts(GrowthKind::None, 1.0, 1.0, 0)},
        };
        Rng rng(1, RngStream::Test);
        double worst = 0;
        for (const Case& c : cases) {
            const GrowthField field(c.options, c.surface);
            for (int i = 0; i < 5; ++i) {
                const Vec3 x(rng.uniform(-2, 2), rng.uniform(-2, 2),
                             c.surface == SurfaceKind::Plane ? 0.0 : rng.uniform(-2, 2));
                const Mat3 J = test::finite_jacobian([&](const Vec3& p) { return field.velocity(p); }, x);
                CAPTURE(c.options.angle_deg);
                CHECK((J - field.tensor()).norm() < 1e-8);
                worst = std::max(worst, (J - field.tensor()).norm());
            }
            // Symmetric: no vorticity, so small-strain elasticity suffices (digest §1.10 [D]).
            CHECK((field.tensor() - field.tensor().transpose()).norm() < 1e-15);
        }
        test::record_claim("3.5/3.6", "the numerical Jacobian of v equals T_G (12 fields, 3 surfaces)",
                           "largest ‖J_numerical − T_G‖", worst, "< 1e-8");
    }

    TEST_CASE("growth: the plane's tensor is the digest's T_G with α measured from Y (α = 90° − angle)") {
        const double r1 = 1.0, r2 = 0.2;
        double worst = 0;
        for (double angle : {0.0, 30.0, 45.0, 90.0, 135.0}) {
            const GrowthField field(opts(GrowthKind::Anisotropic, r1, r2, angle), SurfaceKind::Plane);
            const double a = (90.0 - angle) * DEG_TO_RAD;
            const double s = std::sin(a), c = std::cos(a);
            Mat3 T;
            T << r1 * s * s + r2 * c * c, (r1 - r2) * s * c, 0, (r1 - r2) * s * c, r1 * c * c + r2 * s * s, 0, 0, 0, 0;
            CAPTURE(angle);
            CHECK((field.tensor() - T).norm() < 1e-14);
            worst = std::max(worst, (field.tensor() - T).norm());
        }
        test::record_claim("3.5/3.6", "T_G is the digest's tensor with α measured from Y", "largest ‖T − T_G(α)‖",
                           worst, "< 1e-14");
    }

    TEST_CASE(
        "growth: the unit circle maps to the predicted ellipse with semi-axes 1 + t·r1 and 1 + t·r2 (Figs. 3.5-3.6)") {
        double worst = 0;
        for (double angle : {0.0, 30.0, 90.0}) {
            const double r1 = 1.0, r2 = 0.2, t = 0.7;
            const GrowthField field(opts(GrowthKind::Anisotropic, r1, r2, angle), SurfaceKind::Plane);
            const Vec3 centre(0.3, -0.2, 0);
            const Vec3 d1(std::cos(angle * DEG_TO_RAD), std::sin(angle * DEG_TO_RAD), 0);
            const Vec3 d2(-d1.y(), d1.x(), 0);
            const Vec3 c_t = field.position(centre, t);
            for (int k = 0; k < 72; ++k) {
                const double phi = k * TWO_PI / 72;
                const Vec3 p = centre + std::cos(phi) * Vec3::UnitX() + std::sin(phi) * Vec3::UnitY();
                const Vec3 q = field.position(p, t) - c_t;
                // On the ellipse (q·d1 / a)² + (q·d2 / b)² = 1 with a = 1 + t r1, b = 1 + t r2.
                const double e = sqr(q.dot(d1) / (1 + t * r1)) + sqr(q.dot(d2) / (1 + t * r2));
                REQUIRE(e == doctest::Approx(1.0).epsilon(1e-12));
                worst = std::max(worst, std::abs(e - 1.0));
            }
        }
        test::record_claim("3.5/3.6", "the unit circle maps to an ellipse with semi-axes 1 + t·r1, 1 + t·r2",
                           "largest |(q·d1/a)² + (q·d2/b)² − 1| over 72 points, 3 angles", worst,
                           "< 1e-12·(1 + e) ≈ 2e-12");
        double iso_worst = 0;
        // Isogonic: circles stay circles of the same radius everywhere.
        const GrowthField iso(opts(GrowthKind::Isogonic, 0.5, 0.0, 0), SurfaceKind::Plane);
        for (const Vec3& centre : {Vec3(0, 0, 0), Vec3(5, -3, 0)}) {
            for (int k = 0; k < 12; ++k) {
                const Vec3 dir(std::cos(k * 0.5), std::sin(k * 0.5), 0);
                CHECK((iso.position(centre + dir, 2.0) - iso.position(centre, 2.0)).norm() == doctest::Approx(2.0));
                iso_worst = std::max(
                    iso_worst, std::abs((iso.position(centre + dir, 2.0) - iso.position(centre, 2.0)).norm() - 2.0));
            }
        }
        test::record_claim("3.5/3.6", "isogonic growth keeps circles", "largest |radius − 2| of a grown unit circle",
                           iso_worst, "< 1.2e-5·(1 + 2) (doctest Approx default)");
    }

    TEST_CASE("growth: on the trunk growth is circumferential only and a tangent circle becomes a (1 + rt):1 ellipse") {
        const double r = 0.8, t = 1.5, R = 0.3;
        const GrowthField field(opts(GrowthKind::Anisotropic, r, 0.0, 0), SurfaceKind::Cylinder);
        double worst = 0;
        for (double alpha : {0.0, 1.0, 2.5}) {
            const Vec3 p(R * std::cos(alpha), R * std::sin(alpha), 0.4);
            const Vec3 e1(-std::sin(alpha), std::cos(alpha), 0); // around
            const Vec3 e2(0, 0, 1);                              // along the axis
            CHECK(field.rate_along(e1) == doctest::Approx(r));
            CHECK(field.rate_along(e2) == doctest::Approx(0.0));
            // A small circle in the tangent plane: its image's extent around vs along the axis.
            const double eps = 1e-4;
            const Vec3 around = field.position(p + eps * e1, t) - field.position(p - eps * e1, t);
            const Vec3 along = field.position(p + eps * e2, t) - field.position(p - eps * e2, t);
            CHECK(around.norm() / along.norm() == doctest::Approx(1 + r * t).epsilon(1e-9));
            worst = std::max(worst, std::abs(around.norm() / along.norm() - (1 + r * t)));
            // Points on the trunk stay on a (grown) trunk: the radius scales by 1 + rt.
            const Vec3 q = field.position(p, t);
            CHECK(std::hypot(q.x(), q.y()) == doctest::Approx(R * (1 + r * t)));
            CHECK(q.z() == doctest::Approx(p.z()));
        }
        test::record_claim("3.7/3.8", "cylinder: a tangent circle becomes a (1 + rt):1 ellipse",
                           "largest |axis ratio − (1 + rt)|, rt = 1.2", worst, "< 1e-9·(1 + 2.2)");
    }

    TEST_CASE("growth: the sphere grows isogonically and the anisotropic sphere stretches along z") {
        const GrowthField iso(opts(GrowthKind::Isogonic, 0.5, 0.0, 0), SurfaceKind::Sphere);
        Rng rng(3, RngStream::Test);
        double worst = 0;
        for (int i = 0; i < 10; ++i) {
            const Vec3 n = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
            Vec3 e = n.cross(Vec3(rng.normal(), rng.normal(), rng.normal())).normalized();
            CHECK(iso.rate_along(e) == doctest::Approx(0.5)); // every tangent direction alike
            CHECK((iso.tensor() * e - 0.5 * e).norm() < 1e-14);
            worst = std::max(worst, (iso.tensor() * e - 0.5 * e).norm());
        }
        test::record_claim("3.7/3.8", "sphere: isogonic, every tangent direction grows alike",
                           "largest ‖T·e − r·e‖ over 10 random tangents e", worst, "< 1e-14");
        const GrowthField z4(opts(GrowthKind::Anisotropic, 1.0, 4.0, 0), SurfaceKind::Sphere);
        CHECK(z4.rate_along(Vec3::UnitZ()) == doctest::Approx(4.0));
        CHECK(z4.rate_along(Vec3::UnitX()) == doctest::Approx(1.0));
    }

    TEST_CASE("growth: on periodic domains the period grows with the background") {
        const GrowthField field(opts(GrowthKind::Anisotropic, 1.0, 0.25, 0), SurfaceKind::Plane);
        const Vec3 period_u(2.0, 0, 0), period_v(0, 3.0, 0);
        const double t = 0.8;
        CHECK((field.period_shift(period_u, t) - Vec3(2.0 * (1 + t), 0, 0)).norm() < 1e-14);
        CHECK((field.period_shift(period_v, t) - Vec3(0, 3.0 * (1 + 0.25 * t), 0)).norm() < 1e-14);
        // A point and its periodic copy stay one (grown) period apart: the torus stays a torus.
        const Vec3 x(0.4, 1.1, 0);
        CHECK((field.position(x + period_u, t) - field.position(x, t) - field.period_shift(period_u, t)).norm()
              < 1e-14);
        // Axial growth of a trunk grows its height period.
        const GrowthField trunk(opts(GrowthKind::Anisotropic, 1.0, 0.5, 0), SurfaceKind::Cylinder);
        CHECK(trunk.period_shift(Vec3(0, 0, 2.0), 1.0).z() == doctest::Approx(3.0));
    }
}
