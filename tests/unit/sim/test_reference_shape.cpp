#include "sim/reference_shape.hpp"
#include "support/accuracy.hpp"

#include <doctest/doctest.h>

#include <algorithm>

using namespace crackle;

TEST_SUITE("sim") {
    TEST_CASE("reference shape: zero shrinkage is a straight extrusion along the normal (Fig. 3.10)") {
        const std::array<Vec3, 3> tri = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.2, 0.9, 0)};
        const Vec3 n = Vec3::UnitZ();
        const auto w = sim::reference_shape(tri, n, 0.3, 0.0, 0.0);
        double worst = 0;
        for (std::size_t i = 0; i < 3; ++i) {
            CHECK((w[i] - tri[i]).norm() < 1e-15);
            CHECK((w[i + 3] - (tri[i] + 0.3 * n)).norm() < 1e-15);
            worst = std::max({worst, (w[i] - tri[i]).norm(), (w[i + 3] - (tri[i] + 0.3 * n)).norm()});
        }
        test::record_claim("3.9/3.10", "zero shrinkage is an extrusion along the normal",
                           "largest node distance from the extruded prism", worst, "< 1e-15");
    }

    TEST_CASE("reference shape: uneven shrinkage scales top and bottom about the centroid (Fig. 3.9-3.10)") {
        const std::array<Vec3, 3> tri = {Vec3(1, 2, 3), Vec3(2, 2.5, 3.2), Vec3(1.2, 3.1, 2.6)};
        const Vec3 n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
        const double h = 0.05, s_top = 0.3, s_bot = 0.1;
        const auto w = sim::reference_shape(tri, n, h, s_top, s_bot);
        const Vec3 c = (tri[0] + tri[1] + tri[2]) / 3.0;
        const Vec3 c_bot = (w[0] + w[1] + w[2]) / 3.0, c_top = (w[3] + w[4] + w[5]) / 3.0;
        CHECK((c_bot - c).norm() < 1e-14);
        // centroid_top − centroid_bot = h'·n with h' = h(1 − ½(s_top + s_bot))
        CHECK((c_top - c_bot - h * (1 - 0.5 * (s_top + s_bot)) * n).norm() < 1e-14);
        test::record_claim("3.9/3.10", "uneven shrinkage: centroid offset = h'·n", "‖c_top − c_bot − h'·n‖",
                           (c_top - c_bot - h * (1 - 0.5 * (s_top + s_bot)) * n).norm(), "< 1e-14");
        double worst = 0;
        for (std::size_t i = 0; i < 3; ++i) {
            const std::size_t j = (i + 1) % 3;
            const double edge = (tri[j] - tri[i]).norm();
            CHECK((w[j] - w[i]).norm() == doctest::Approx((1 - s_bot) * edge));
            CHECK((w[j + 3] - w[i + 3]).norm() == doctest::Approx((1 - s_top) * edge));
            worst = std::max({worst, std::abs((w[j] - w[i]).norm() - (1 - s_bot) * edge),
                              std::abs((w[j + 3] - w[i + 3]).norm() - (1 - s_top) * edge)});
        }
        test::record_claim("3.9/3.10", "uneven shrinkage: top and bottom scale by 1 − s_top, 1 − s_bot",
                           "largest |edge length − (1 − s)·edge|", worst,
                           "< 1.2e-5·(1 + edge) (doctest Approx default)");
        // Negative rates expand.
        const auto e = sim::reference_shape(tri, n, h, -0.5, 0.0);
        CHECK((e[4] - e[3]).norm() == doctest::Approx(1.5 * (tri[1] - tri[0]).norm()));
    }

    TEST_CASE("shrinkage: linear functions s(t) = rate·t") {
        const sim::ShrinkageOptions s{0.25, -0.5};
        CHECK(s.top(2.0) == doctest::Approx(0.5));
        CHECK(s.bottom(1.0) == doctest::Approx(-0.5));
        CHECK(s.top(0.0) == 0.0);
    }
}
