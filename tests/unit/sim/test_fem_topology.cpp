// Topology changes (edge splits, Rivara bisection, vertex moves, edge flips) on every surface:
// in a layer that carries no stress they must create none, and wherever the layer is loaded they
// must not change the energy before relaxation.
#include "core/rng.hpp"
#include "sim/fem_model.hpp"
#include "support/fem_fixture.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;
using test::Layer;
using test::LayerSpec;

namespace {

/// A layer that grows with its background: isogonic growth r and material expansion r (a
/// negative shrinkage), with a thickness that varies (noise) so resampling it matters.
LayerSpec free_growth(SurfaceKind kind) {
    LayerSpec spec;
    spec.kind = kind;
    spec.size = kind == SurfaceKind::Sphere ? Vec2(0.06, 0.06) : Vec2(0.2, 0.2);
    spec.elements = 500;
    spec.growth = {sim::GrowthKind::Isogonic, 0.02, 0.02, 0.0};
    spec.shrinkage = {-0.02, -0.02};
    spec.thickness_variation.pattern = sim::PatternKind::Noise;
    spec.thickness_variation.amplitude = 0.4;
    spec.thickness_variation.scale = 0.03;
    spec.fem.tolerance = 1e-12;
    spec.fem.stiffness_refresh = 0.0;
    return spec;
}

/// Largest |σ| and |σ̇| component over the alive elements' top Gauss points.
std::pair<double, double> max_stress(const sim::FemModel& m) {
    double s = 0, r = 0;
    for (std::size_t f = 0; f < m.mesh().num_faces(); ++f) {
        if (!m.alive(mesh::face_id(f))) continue;
        for (const auto& sigma : m.top_stress(mesh::face_id(f)))
            s = std::max(s, sigma.cwiseAbs().maxCoeff());
        for (const auto& rate : m.top_stress_rate(mesh::face_id(f)))
            r = std::max(r, rate.cwiseAbs().maxCoeff());
    }
    return {s, r};
}

/// Whether flipping edge k of f gives two positively oriented triangles (a convex quad).
bool convex_flip(const sim::FemModel& model, mesh::FaceId f, int k) {
    const mesh::SurfaceMesh& m = model.mesh();
    const mesh::FaceNeighbor nb = m.neighbor(f, k);
    if (nb.face == mesh::NO_FACE || nb.face == f) return false;
    // The quad a, d, b, c in f's frame; the flip gives (a, d, c) and (d, b, c).
    const Vec3 a = m.corner_position(f, k), b = m.corner_position(f, (k + 1) % 3),
               c = m.corner_position(f, (k + 2) % 3);
    const Vec3 d = m.corner_position(nb.face, (nb.edge + 2) % 3) + (a - m.corner_position(nb.face, (nb.edge + 1) % 3));
    auto positive = [&](const Vec3& p, const Vec3& q, const Vec3& r) {
        const Vec3 n = model.surface().frame(Vec3((p + q + r) / 3.0)).n;
        return (q - p).cross(r - p).dot(n) > 1e-3 * (q - p).squaredNorm();
    };
    return positive(a, d, c) && positive(d, b, c);
}

/// Random splits, bisections, vertex moves and flips, with no relaxation in between.
void scramble(sim::FemModel& m, std::uint64_t seed) {
    Rng rng(seed, RngStream::Test);
    auto face = [&] { return mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(m.mesh().num_faces()))); };
    for (int i = 0; i < 15; ++i)
        m.split_edge(face(), static_cast<int>(rng.uniform_int(3)), 0.25 + 0.5 * rng.uniform());
    for (int i = 0; i < 10; ++i)
        m.subdivide(face());
    for (int i = 0; i < 10; ++i) {
        const mesh::FaceId f = face();
        const int k = static_cast<int>(rng.uniform_int(3));
        Vec3 bary = Vec3::Constant(0.15);
        bary[k] = 0.7; // a step from corner k into its face
        Vec3 top, rate;
        const mesh::NewVertex to = m.face_point(f, bary, &top, &rate);
        m.move_vertex(m.mesh().faces[f].v[static_cast<std::size_t>(k)], to, top, rate);
    }
    for (int flips = 0, tries = 0; flips < 10 && tries < 1000; ++tries) {
        const mesh::FaceId f = face();
        const int k = static_cast<int>(rng.uniform_int(3));
        if (convex_flip(m, f, k)) {
            m.flip_edge(f, k);
            ++flips;
        }
    }
}

} // namespace

TEST_SUITE("sim") {
    TEST_CASE("fem topology: a freely growing layer stays stress free through splits, bisections, moves and flips, "
              "on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            Layer layer(free_growth(kind));
            sim::FemModel& m = *layer.model;
            m.set_time(0.5);
            m.relax();
            m.solve_rate();
            // The stress a bonded layer would carry at this growth: the scale of "zero".
            const double scale = layer.spec.young * 0.02 * 0.5;
            CAPTURE(std::string(mesh::to_string(kind)));
            const auto [s0, r0] = max_stress(m);
            REQUIRE(s0 < 1e-7 * scale);
            REQUIRE(r0 < 1e-7 * scale / 0.5);
            const std::size_t faces = m.mesh().num_faces();
            scramble(m, 3);
            CHECK(m.mesh().num_faces() > faces + 30);
            CHECK(m.mesh().validate().empty());
            const auto [s1, r1] = max_stress(m);
            CHECK(s1 < 1e-7 * scale);
            CHECK(r1 < 1e-7 * scale / 0.5);
            CHECK(m.max_residual_force() < 1e-7 * m.force_scale());
        }
    }
}
