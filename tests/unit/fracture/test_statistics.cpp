#include "fracture/statistics.hpp"
#include "support/accuracy.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

using namespace crackle;

namespace {

/// A pattern on a periodic plane whose removed faces are those hit by `cut`.
fracture::CrackPattern pattern_with(const std::function<bool(const Vec2&)>& cut, std::size_t faces = 2000) {
    fracture::CrackPattern p;
    p.surface = test::make_surface(mesh::SurfaceKind::Plane, 1.0, 1.0);
    p.mesh = test::make_mesh(p.surface, faces, 3);
    p.removed.assign(p.mesh.num_faces(), 0);
    for (std::size_t f = 0; f < p.mesh.num_faces(); ++f) {
        const auto id = mesh::face_id(f);
        const Vec2 c = (p.mesh.corner_domain(id, 0) + p.mesh.corner_domain(id, 1) + p.mesh.corner_domain(id, 2)) / 3.0;
        p.removed[f] = cut(Vec2(wrap(c.x(), 1.0), wrap(c.y(), 1.0))) ? 1 : 0;
    }
    fracture::label_fragments(p);
    p.cracks = fracture::removal_crack_lips(p);
    return p;
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("statistics: junction classes") {
        CHECK(fracture::classify_junction(180, 90, 90) == fracture::JunctionKind::T);
        CHECK(fracture::classify_junction(160, 100, 100) == fracture::JunctionKind::T);
        CHECK(fracture::classify_junction(120, 120, 120) == fracture::JunctionKind::Y);
        CHECK(fracture::classify_junction(140, 110, 110) == fracture::JunctionKind::Y);
        CHECK(fracture::classify_junction(150, 150, 60) == fracture::JunctionKind::Other);
    }

    TEST_CASE("statistics: two straight cracks along v make two fragments with vertical anisotropic cracks") {
        // Bands at u ≈ 0.25 and u ≈ 0.75 cut the torus into two strips.
        const auto p = pattern_with(
            [](const Vec2& c) { return std::abs(c.x() - 0.25) < 0.012 || std::abs(c.x() - 0.75) < 0.012; });
        const auto st = fracture::pattern_statistics(p);
        CHECK(st.fragments == 2);
        CHECK(st.total_area == doctest::Approx(1.0).epsilon(1e-9));
        // Two cracks of length 1 across the unit tile; the lips of a zig-zag band run a little longer.
        CHECK(st.crack_length_per_area == doctest::Approx(2.0).epsilon(0.35));
        CHECK(st.anisotropy > 0.3);
        CHECK(std::abs(st.dominant_angle_deg - 90.0) < 10.0);
        CHECK(st.axial_fraction > 0.3);
        test::record_claim("7.1", "crack density of two straight cracks across the unit tile (exact: 2 /m)",
                           "rho_c of two zig-zag removal bands [1/m]", st.crack_length_per_area,
                           "|ρ_c − 2| < 0.35·(1 + ρ_c)");
        test::record_claim("7.1", "dominant direction of two cracks along v (exact: 90°)", "dominant angle [deg]",
                           st.dominant_angle_deg, "90 ± 10");
    }

    TEST_CASE("statistics: a cross of cracks splits the torus into one fragment and has four-way meetings") {
        const auto p =
            pattern_with([](const Vec2& c) { return std::abs(c.x() - 0.5) < 0.012 || std::abs(c.y() - 0.5) < 0.012; });
        const auto st = fracture::pattern_statistics(p);
        CHECK(st.fragments == 1); // a torus cut once each way stays connected
        CHECK(st.anisotropy < 0.2);
        CHECK(st.psi6 < 0.5);
        test::record_claim("7.1", "a cross of cracks has no anisotropy (exact: 0)", "anisotropy a", st.anisotropy,
                           "< 0.2");
    }

    TEST_CASE("statistics: no cracks give one fragment and zero density") {
        const auto p = pattern_with([](const Vec2&) { return false; }, 500);
        const auto st = fracture::pattern_statistics(p);
        CHECK(st.fragments == 1);
        CHECK(st.crack_length == 0.0);
        CHECK(st.junctions == 0);
        CHECK(st.mean_fragment_area == doctest::Approx(1.0).epsilon(1e-9));
        CHECK(st.min_angle_deg > 10.0);
    }
}
