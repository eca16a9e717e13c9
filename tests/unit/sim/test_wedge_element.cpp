#include "core/rng.hpp"
#include "sim/wedge_element.hpp"
#include "support/accuracy.hpp"

#include <Eigen/Eigenvalues>
#include <doctest/doctest.h>

using namespace crackle;
using namespace crackle::sim;

namespace {

/// A skewed prism: a random triangle extruded along a tilted direction.
wedge::Nodes random_prism(Rng& rng, double height = 0.3) {
    wedge::Nodes n;
    Vec3 a(rng.uniform(), rng.uniform(), 0), b(rng.uniform() + 1, rng.uniform(), 0),
        c(rng.uniform(), rng.uniform() + 1, 0);
    if ((b - a).cross(c - a).z() < 0) std::swap(b, c);
    const Vec3 up(0.1 * rng.uniform(), 0.1 * rng.uniform(), height);
    n = {a, b, c, a + up, b + up, c + up};
    // Rotate the whole prism to a random orientation.
    const Mat3 R = Eigen::AngleAxisd(rng.uniform() * 6, Vec3(rng.normal(), rng.normal(), rng.normal()).normalized())
                       .toRotationMatrix();
    for (Vec3& p : n)
        p = R * p;
    return n;
}

} // namespace

TEST_SUITE("sim") {
    TEST_CASE("wedge: normalised quadrature weights integrate the reference volume while Table 5.1 sums to 2") {
        double sum = 0, xi_eta_zeta2 = 0;
        for (const auto& g : wedge::quadrature()) {
            sum += g.weight;
            xi_eta_zeta2 += g.weight * g.xi * g.eta * g.zeta * g.zeta;
        }
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-15)); // ½ (triangle) × 2 (ζ)
        CHECK(sum * 2 == doctest::Approx(wedge::TABLE_5_1_WEIGHT_SUM));
        // ∫ ξ η ζ² = 1/24 · 2/3 = 1/36 exactly (the digest's check; the printed table gives 2/36).
        CHECK(xi_eta_zeta2 == doctest::Approx(1.0 / 36.0).epsilon(1e-14));
        // The three points nearest the top face are the first three.
        for (int k : wedge::TOP_GAUSS_POINTS)
            CHECK(wedge::quadrature()[static_cast<std::size_t>(k)].zeta > 0.7);
    }

    TEST_CASE("wedge: shape functions interpolate the nodes and sum to one") {
        const std::array<Vec3, 6> iso = {Vec3(1, 0, -1), Vec3(0, 1, -1), Vec3(0, 0, -1),
                                         Vec3(1, 0, 1),  Vec3(0, 1, 1),  Vec3(0, 0, 1)};
        for (std::size_t j = 0; j < 6; ++j) {
            const wedge::Vec6 N = wedge::shape_functions(iso[j].x(), iso[j].y(), iso[j].z());
            for (std::size_t i = 0; i < 6; ++i)
                CHECK(N[static_cast<Eigen::Index>(i)] == doctest::Approx(i == j ? 1.0 : 0.0));
        }
        CHECK(wedge::shape_functions(0.2, 0.3, 0.4).sum() == doctest::Approx(1.0));
        // Derivatives against central differences.
        const double h = 1e-6, x = 0.21, y = 0.33, z = -0.4;
        const wedge::Mat3x6 d = wedge::shape_derivatives(x, y, z);
        const wedge::Vec6 dx = (wedge::shape_functions(x + h, y, z) - wedge::shape_functions(x - h, y, z)) / (2 * h);
        const wedge::Vec6 dz = (wedge::shape_functions(x, y, z + h) - wedge::shape_functions(x, y, z - h)) / (2 * h);
        CHECK((d.row(0).transpose() - dx).norm() < 1e-9);
        CHECK((d.row(2).transpose() - dz).norm() < 1e-9);
    }

    TEST_CASE("wedge: Σ w det J is the volume of skewed prisms") {
        Rng rng(3, RngStream::Test);
        double worst = 0;
        for (int i = 0; i < 10; ++i) {
            const wedge::Nodes n = random_prism(rng, 0.2 + 0.1 * i);
            const double exact = 0.5 * (n[1] - n[0]).cross(n[2] - n[0]).dot(n[3] - n[0]);
            CHECK(wedge::volume(n) == doctest::Approx(exact).epsilon(1e-12));
            worst = std::max(worst, std::abs(wedge::volume(n) - exact));
        }
        test::record_claim("7.3 wedge patch tests", "Σ w·det J is the volume of skewed prisms",
                           "largest |Σ w·det J − V| over 10 prisms", worst, "< 1e-12·(1 + V)");
    }

    TEST_CASE("wedge: K_e is symmetric positive semi-definite with exactly six zero eigenvalues") {
        Rng rng(5, RngStream::Test);
        int off = 0;
        for (int i = 0; i < 5; ++i) {
            const wedge::Mat18 K = wedge::stiffness(random_prism(rng), 1e9, 0.3);
            CHECK((K - K.transpose()).norm() <= 1e-14 * K.norm());
            Eigen::SelfAdjointEigenSolver<wedge::Mat18> eig(K);
            const auto& ev = eig.eigenvalues();
            const double scale = ev.maxCoeff();
            int zeros = 0;
            for (int k = 0; k < 18; ++k) {
                CHECK(ev[k] > -1e-10 * scale);
                zeros += std::abs(ev[k]) < 1e-10 * scale;
            }
            CHECK(zeros == 6);
            CHECK(ev[6] > 1e-4 * scale); // the seventh is a real deformation mode
            off = std::max(off, std::abs(zeros - 6));
        }
        test::record_claim("7.3 wedge patch tests", "K_e has exactly the six rigid-body zero modes",
                           "largest |zero eigenvalues − 6| over 5 prisms", off, "= 0");
    }

    TEST_CASE(
        "wedge: K_e built from B's non-zeros equals the dense quadrature sum of Bᵀ D B (isotropic and anisotropic D)") {
        Rng rng(11, RngStream::Test);
        for (int trial = 0; trial < 20; ++trial) {
            const wedge::Nodes n = random_prism(rng, 0.05 + 0.5 * rng.uniform());
            wedge::Mat6 D = wedge::elasticity(1e7 * (1 + rng.uniform()), 0.45 * rng.uniform());
            if (trial % 2) { // a general symmetric positive definite D, as edge damage makes
                const wedge::Mat6 A = wedge::Mat6::Random();
                D += 1e6 * A * A.transpose();
            }
            wedge::Mat18 dense = wedge::Mat18::Zero();
            for (const auto& g : wedge::quadrature()) {
                double det = 0;
                const wedge::Mat6x18 B = wedge::strain_matrix(n, g.xi, g.eta, g.zeta, &det);
                dense += (g.weight * det) * (B.transpose() * D * B);
            }
            dense = 0.5 * (dense + dense.transpose());
            const wedge::Mat18 K = wedge::stiffness(n, D);
            CHECK((K - dense).norm() <= 1e-13 * dense.norm());
            CHECK(K == K.transpose());
        }
    }

    TEST_CASE("wedge: rigid translations and rotations give zero force") {
        Rng rng(7, RngStream::Test);
        const wedge::Nodes n = random_prism(rng);
        const wedge::Mat18 K = wedge::stiffness(n, 2e10, 0.25);
        const Vec3 t(0.3, -1.2, 0.7), w(0.2, 0.5, -0.9);
        wedge::Vec18 translation, rotation;
        for (std::size_t i = 0; i < 6; ++i) {
            translation.segment<3>(static_cast<Eigen::Index>(3 * i)) = t;
            rotation.segment<3>(static_cast<Eigen::Index>(3 * i)) = w.cross(n[i]); // infinitesimal rotation
        }
        CHECK((K * translation).norm() < 1e-10 * K.norm() * translation.norm());
        CHECK((K * rotation).norm() < 1e-10 * K.norm() * rotation.norm());
        test::record_claim("7.3 wedge patch tests", "rigid motions give zero force",
                           "‖K·q_rot‖ / (‖K‖·‖q_rot‖), infinitesimal rotation",
                           (K * rotation).norm() / (K.norm() * rotation.norm()), "< 1e-10");
    }

    TEST_CASE("wedge: a linear displacement field gives the exact constant stress (patch test)") {
        Rng rng(9, RngStream::Test);
        const double E = 3e9, nu = 0.3;
        const wedge::Mat6 D = wedge::elasticity(E, nu);
        double worst = 0;
        for (int trial = 0; trial < 5; ++trial) {
            const wedge::Nodes n = random_prism(rng);
            Mat3 A;
            for (int i = 0; i < 9; ++i)
                A(i / 3, i % 3) = 1e-3 * rng.normal();
            const Vec3 c(rng.normal(), rng.normal(), rng.normal());
            wedge::Vec18 q;
            for (std::size_t i = 0; i < 6; ++i)
                q.segment<3>(static_cast<Eigen::Index>(3 * i)) = A * n[i] + c;
            // ε = sym(A) in Voigt order with engineering shears
            wedge::Vec6 eps;
            eps << A(0, 0), A(1, 1), A(2, 2), A(1, 2) + A(2, 1), A(2, 0) + A(0, 2), A(0, 1) + A(1, 0);
            const wedge::Vec6 expected = D * eps;
            for (const auto& g : wedge::quadrature()) {
                const wedge::Vec6 s = wedge::stress(n, D, q, g.xi, g.eta, g.zeta);
                CHECK((s - expected).norm() <= 1e-9 * expected.norm());
                worst = std::max(worst, (s - expected).norm() / expected.norm());
            }
        }
        test::record_claim("7.3 wedge patch tests", "a linear displacement gives the exact constant stress",
                           "largest relative stress error at the Gauss points, 5 skewed prisms", worst, "<= 1e-9");
    }

    TEST_CASE("wedge: principal stresses of a known tensor") {
        wedge::Vec6 s;
        s << 3, 1, 0, 0, 0, 0; // σxx = 3, σyy = 1
        const auto p = wedge::max_principal(s);
        CHECK(p.value == doctest::Approx(3.0));
        CHECK(std::abs(p.direction.x()) == doctest::Approx(1.0));
        s << 1, 1, 0, 0, 0, 1; // τxy = 1: principal 2 along (1, 1)/√2
        const auto q = wedge::max_principal(s);
        CHECK(q.value == doctest::Approx(2.0));
        CHECK(std::abs(q.direction.x()) == doctest::Approx(std::sqrt(0.5)));
    }
}
