#include "core/error.hpp"
#include "sim/fem_model.hpp"
#include "support/accuracy.hpp"
#include "support/fem_fixture.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;
using test::Layer;
using test::LayerSpec;

namespace {

/// Largest |σ| component over every alive element's top Gauss points.
double max_abs_stress(const sim::FemModel& m) {
    double s = 0;
    for (std::size_t f = 0; f < m.mesh().num_faces(); ++f) {
        if (!m.alive(mesh::face_id(f))) continue;
        for (const auto& sigma : m.top_stress(mesh::face_id(f)))
            s = std::max(s, sigma.cwiseAbs().maxCoeff());
    }
    return s;
}

/// Checks every element's top stress against a constant biaxial state σxx = σyy = σ, rest 0.
double max_relative_deviation_from_biaxial(const sim::FemModel& m, double sigma) {
    double worst = 0;
    for (std::size_t f = 0; f < m.mesh().num_faces(); ++f) {
        for (const auto& s : m.top_stress(mesh::face_id(f))) {
            const double dev = std::max({std::abs(s[0] - sigma), std::abs(s[1] - sigma), std::abs(s[2]), std::abs(s[3]),
                                         std::abs(s[4]), std::abs(s[5])});
            worst = std::max(worst, dev / std::abs(sigma));
        }
    }
    return worst;
}

} // namespace

TEST_SUITE("sim") {
    TEST_CASE("fem: a layer with no growth and no shrinkage carries zero stress on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.3, 0.2);
            Layer layer(spec);
            layer.model->set_time(0.5);
            layer.model->relax();
            CAPTURE(mesh::to_string(kind));
            CHECK(max_abs_stress(*layer.model) < 1e-9 * spec.young);
            CHECK(layer.model->strain_energy() < 1e-20);
        }
    }

    TEST_CASE("fem: a uniformly shrinking film on a rigid background has the biaxial stress E·ε/(1-ν)") {
        LayerSpec spec;
        spec.shrinkage = {0.02, 0.02};    // isotropic: s(t) = 0.02 t at top and bottom
        spec.fem.stiffness_refresh = 0.0; // build K at the exact reference shape
        spec.fem.tolerance = 1e-12;
        Layer layer(spec);
        for (double t : {0.05, 0.5}) {
            layer.model->set_time(t);
            layer.model->relax();
            const double s = 0.02 * t;
            const double eps = s / (1 - s); // the pinned bottom stretches the shrunk reference
            const double sigma = spec.young * eps / (1 - spec.poisson);
            CAPTURE(t);
            CHECK(max_relative_deviation_from_biaxial(*layer.model, sigma) < 1e-6);
        }
    }

    TEST_CASE("fem: isogonic background growth stresses the film uniformly across the periodic seam") {
        LayerSpec spec;
        spec.growth = {sim::GrowthKind::Isogonic, 0.01, 0.01, 0.0};
        spec.fem.tolerance = 1e-12;
        Layer layer(spec);
        layer.model->set_time(0.3);
        layer.model->relax();
        const double sigma = spec.young * 0.01 * 0.3 / (1 - spec.poisson);
        CHECK(max_relative_deviation_from_biaxial(*layer.model, sigma) < 1e-6);
    }

    TEST_CASE("fem: growth by s and shrinkage by 1/s give the same stresses on every surface (digest 7.3)") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            // A non-uniform layer (noisy stiffness, a few elements removed) so the field has
            // structure. Isogonic growth scales the cylinder and the sphere as a whole.
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.3, 0.2);
            spec.young_variation.pattern = sim::PatternKind::Noise;
            spec.young_variation.amplitude = 0.5;
            spec.young_variation.scale = 0.05;
            spec.fem.stiffness_refresh = 0.0;
            spec.fem.tolerance = 1e-12;
            const double r = 0.02, t = 0.5, s = 1 + r * t;
            LayerSpec grow = spec, shrink = spec;
            grow.growth = {sim::GrowthKind::Isogonic, r, r, 0.0};
            // Shrink the reference (in plane and height) by 1/s at the same time t.
            const double rate = (1 - 1 / s) / t;
            shrink.shrinkage = {rate, rate};
            Layer a(grow), b(shrink);
            for (std::size_t f : {3u, 40u, 41u, 120u}) {
                a.model->remove_element(mesh::face_id(f));
                b.model->remove_element(mesh::face_id(f));
            }
            a.model->set_time(t);
            b.model->set_time(t);
            a.model->relax();
            b.model->relax();
            double worst = 0, scale = 0;
            for (std::size_t f = 0; f < a.model->mesh().num_faces(); ++f) {
                if (!a.model->alive(mesh::face_id(f))) continue;
                const auto sa = a.model->top_stress(mesh::face_id(f));
                const auto sb = b.model->top_stress(mesh::face_id(f));
                for (std::size_t k = 0; k < 3; ++k) {
                    worst = std::max(worst, (sa[k] - sb[k]).cwiseAbs().maxCoeff());
                    scale = std::max(scale, sa[k].cwiseAbs().maxCoeff());
                }
            }
            CHECK(scale > 0);
            CHECK(worst < 1e-6 * scale);
            test::record_claim("7.3 growth≡shrinkage",
                               std::string("growth by s and shrinkage by 1/s: the same stress field (FEM, ")
                                   + mesh::to_string(kind) + ")",
                               "largest stress difference / largest stress", worst / scale, "< 1e-6");
        }
    }

    TEST_CASE("fem: local matrix updates after element removal equal a full reassembly to round-off") {
        LayerSpec spec;
        spec.kind = SurfaceKind::Cylinder;
        Layer layer(spec);
        Rng rng(4, RngStream::Test);
        for (int i = 0; i < 40; ++i) {
            const auto f = mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(layer.model->mesh().num_faces())));
            if (layer.model->alive(f)) layer.model->remove_element(f);
        }
        const auto& local = layer.model->stiffness();
        const auto full = layer.model->assemble_from_scratch();
        const double diff = (Eigen::MatrixXd(local) - Eigen::MatrixXd(full)).cwiseAbs().maxCoeff();
        CHECK(diff <= 1e-12 * Eigen::MatrixXd(full).cwiseAbs().maxCoeff());
    }

    TEST_CASE("fem: conjugate gradient and the sparse Cholesky agree, on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.3, 0.2);
            spec.growth = {sim::GrowthKind::Anisotropic, 0.02, 0.005, kind == SurfaceKind::Plane ? 30.0 : 0.0};
            spec.shrinkage = {0.01, 0.0};
            spec.fem.tolerance = 1e-12;
            LayerSpec direct = spec;
            direct.fem.solver = sim::SolverKind::Direct;
            Layer a(spec), b(direct);
            for (std::size_t f : {5u, 6u, 7u}) {
                a.model->remove_element(mesh::face_id(f));
                b.model->remove_element(mesh::face_id(f));
            }
            a.model->set_time(0.7);
            b.model->set_time(0.7);
            const auto stats = a.model->relax();
            b.model->relax();
            CHECK(stats.iterations > 0);
            double diff = 0, disp = 0;
            for (std::size_t v = 0; v < a.model->mesh().num_vertices(); ++v) {
                const auto id = mesh::vertex_id(v);
                diff = std::max(diff, (a.model->top_position(id) - b.model->top_position(id)).norm());
                disp = std::max(disp, (a.model->top_position(id) - a.model->bottom_position(id)).norm());
            }
            CHECK(diff < 1e-8 * disp);
        }
    }

    TEST_CASE("fem: the equilibrium is affine in time while the stiffness is fixed, on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.3, 0.2);
            spec.growth = {sim::GrowthKind::Anisotropic, 0.03, 0.0, 0.0};
            spec.shrinkage = {0.004, 0.001}; // stays within the stiffness refresh tolerance
            spec.fem.tolerance = 1e-12;
            Layer a(spec), b(spec);
            a.model->remove_element(mesh::face_id(10));
            b.model->remove_element(mesh::face_id(10));
            a.model->set_time(0.2);
            a.model->relax();
            a.model->solve_rate();
            CHECK(a.model->stiffness_horizon() > 1.5);
            a.model->set_time(1.4);
            a.model->advance_along_rate(1.2);
            b.model->set_time(1.4);
            b.model->relax();
            for (std::size_t f : {0u, 50u, 200u}) {
                const auto id = mesh::face_id(f);
                CHECK(a.model->stress_ratio(id) == doctest::Approx(b.model->stress_ratio(id)).epsilon(1e-7));
            }
            // ...and the stress rate predicts the stress change.
            Layer c(spec);
            c.model->set_time(0.2);
            c.model->relax();
            c.model->solve_rate();
            const auto s0 = c.model->top_stress(mesh::face_id(7));
            const auto rate = c.model->top_stress_rate(mesh::face_id(7));
            c.model->set_time(0.9);
            c.model->relax();
            const auto s1 = c.model->top_stress(mesh::face_id(7));
            CHECK((s1[0] - (s0[0] + 0.7 * rate[0])).norm() < 1e-7 * s1[0].norm());
        }
    }

    TEST_CASE("fem: moving along the affine solution rebuilds the stiffness at each refresh horizon, on every "
              "surface") {
        // Shrinkage five times the refresh tolerance: time lands exactly on each horizon, and
        // each landing must rebuild K from the shrunk shapes (it once did not, and every later
        // stress came from the t = 0 shapes).
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.2, 0.2);
            spec.shrinkage = {0.05, 0.03};
            spec.growth = {sim::GrowthKind::Isogonic, 0.01, 0.01, 0.0};
            spec.fem.tolerance = 1e-12;
            Layer a(spec);
            a.model->relax();
            a.model->solve_rate();
            const std::size_t builds = a.model->stiffness_builds();
            while (a.model->time() < 1.0) {
                a.model->advance_time(std::min(1.0, a.model->stiffness_horizon()));
                if (a.model->stiffness_changed()) {
                    a.model->relax();
                    a.model->solve_rate();
                }
            }
            CAPTURE(mesh::to_string(kind));
            // The top shrinks 0.01 per 0.2: rebuilt at 0.2, 0.4, 0.6, 0.8 and 1.0.
            CHECK(a.model->stiffness_builds() - builds == 5);
            // ...so at t = 1 the stresses are those of K built at the exact shapes.
            LayerSpec exact = spec;
            exact.fem.stiffness_refresh = 0.0;
            Layer b(exact);
            b.model->set_time(1.0);
            b.model->relax();
            double worst = 0, scale = 0;
            for (std::size_t f = 0; f < b.model->mesh().num_faces(); ++f) {
                const auto sa = a.model->top_stress(mesh::face_id(f));
                const auto sb = b.model->top_stress(mesh::face_id(f));
                for (std::size_t k = 0; k < 3; ++k) {
                    worst = std::max(worst, (sa[k] - sb[k]).cwiseAbs().maxCoeff());
                    scale = std::max(scale, sb[k].cwiseAbs().maxCoeff());
                }
            }
            CHECK(scale > 0);
            CHECK(worst < 1e-6 * scale);
        }
    }

    TEST_CASE("fem: a solver that cannot converge reports iterations and residual") {
        LayerSpec spec;
        spec.growth = {sim::GrowthKind::Isogonic, 0.01, 0.01, 0.0};
        spec.fem.max_iterations = 2;
        Layer layer(spec);
        layer.model->set_time(1.0);
        try {
            layer.model->relax();
            FAIL("expected a NumericError");
        } catch (const NumericError& e) {
            const std::string what = e.what();
            CHECK(what.find("2 iterations") != std::string::npos);
            CHECK(what.find("residual") != std::string::npos);
        }
    }

    TEST_CASE("fem: Rivara subdivision keeps the mesh conforming and the solution exact for uniform loads") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.2, 0.2);
            spec.growth = {sim::GrowthKind::Isogonic, 0.01, 0.01, 0.0};
            spec.fem.tolerance = 1e-12;
            Layer layer(spec);
            const double min_angle_before = mesh::mesh_quality(layer.model->mesh()).min_angle_deg;
            Rng rng(2, RngStream::Test);
            for (int i = 0; i < 30; ++i)
                layer.model->subdivide(
                    mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(layer.model->mesh().num_faces()))));
            const auto& m = layer.model->mesh();
            CAPTURE(mesh::to_string(kind));
            CHECK(m.validate() == "");
            CHECK(m.num_boundary_edges() == 0);
            CHECK(m.euler_characteristic() == (kind == SurfaceKind::Sphere ? 2 : 0));
            CHECK(m.num_faces() > spec.elements + 30);
            // Longest-edge bisection at most halves the smallest angle (Rivara's bound).
            CHECK(mesh::mesh_quality(m).min_angle_deg > 0.5 * min_angle_before);
            if (kind == SurfaceKind::Plane) {
                layer.model->set_time(0.5);
                layer.model->relax();
                const double sigma = spec.young * 0.005 / (1 - spec.poisson);
                CHECK(max_relative_deviation_from_biaxial(*layer.model, sigma) < 1e-6);
            }
        }
    }
}
