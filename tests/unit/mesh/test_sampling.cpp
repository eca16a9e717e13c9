#include "mesh/sampling.hpp"
#include "mesh/triangulate.hpp"
#include "support/accuracy.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <numeric>

using namespace crackle;
using mesh::SurfaceKind;

namespace {

double fraction_below_10deg(const mesh::SurfaceMesh& m) {
    return mesh::mesh_quality(m).fraction_below_10deg;
}

/// Histogram of edge directions (mod 180°) in 10° bins, from the unrolled domain.
std::array<double, 18> edge_orientation_histogram(const mesh::SurfaceMesh& m) {
    std::array<double, 18> h{};
    for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
        const auto f = mesh::face_id(fi);
        for (int k = 0; k < 3; ++k) {
            const Vec2 d = m.corner_domain(f, (k + 1) % 3) - m.corner_domain(f, k);
            double a = std::atan2(d.y(), d.x()) * RAD_TO_DEG;
            a = wrap(a, 180.0);
            h[static_cast<std::size_t>(std::min(17.0, a / 10.0))] += 1;
        }
    }
    return h;
}

double peak_ratio(const std::array<double, 18>& h) {
    double sum = 0, mx = 0;
    for (double v : h) {
        sum += v;
        mx = std::max(mx, v);
    }
    return mx / (sum / 18.0);
}

/// Points of a triangular lattice filling the torus (rows 60° apart).
std::vector<Vec2> lattice_points(int cols, int rows, double a) {
    std::vector<Vec2> pts;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
            pts.emplace_back((i + 0.5 * (j % 2) + 0.25) * a, (j + 0.5) * a * std::sqrt(3.0) / 2);
    return pts;
}

} // namespace

TEST_SUITE("mesh") {
    TEST_CASE("sampling: repelled points give far fewer thin triangles than uniform random points (Figs. 5.1-5.2)") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        double repelled_thin = 0, random_thin = 1, repelled_min = 180;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            Rng rng(seed, RngStream::Sampling);
            mesh::SamplingOptions o;
            o.count = 2000;
            const auto repelled = mesh::triangulate_periodic(mesh::sample_periodic(s.period(), o, {}, rng), s);
            Rng rng2(seed, RngStream::Sampling);
            const auto random = mesh::triangulate_periodic(mesh::sample_uniform_random(s.period(), 2000, rng2), s);
            CAPTURE(seed);
            CHECK(fraction_below_10deg(repelled) < 0.002);
            CHECK(fraction_below_10deg(random) > 0.03);
            CHECK(mesh::mesh_quality(repelled).min_angle_deg > 12.0);
            repelled_thin = std::max(repelled_thin, fraction_below_10deg(repelled));
            random_thin = std::min(random_thin, fraction_below_10deg(random));
            repelled_min = std::min(repelled_min, mesh::mesh_quality(repelled).min_angle_deg);
        }
        test::record_claim("5.1/5.2", "repelled points: few degenerate triangles",
                           "share of triangles with min angle < 10°, largest of 3 seeds", repelled_thin, "< 0.002");
        test::record_claim("5.1/5.2", "random points: degenerate triangles",
                           "share of triangles with min angle < 10°, smallest of 3 seeds", random_thin, "> 0.03");
        test::record_claim("5.1/5.2", "repelled points: few degenerate triangles",
                           "smallest angle of any triangle [deg], 3 seeds", repelled_min, "> 12");
    }

    TEST_CASE("sampling: edge orientations are flat for repelled points but peak three times for a lattice") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        Rng rng(4, RngStream::Sampling);
        mesh::SamplingOptions o;
        o.count = 3000;
        const auto repelled = mesh::triangulate_periodic(mesh::sample_periodic(s.period(), o, {}, rng), s);
        const auto h = edge_orientation_histogram(repelled);
        CHECK(peak_ratio(h) < 1.35);
        test::record_claim("5.1/5.2", "repelled points: random edge orientation",
                           "largest 10° bin of the edge-orientation histogram / mean bin", peak_ratio(h), "< 1.35");

        // A 40 × 46 triangular lattice on a torus sized to fit it exactly.
        const double a = 1.0 / 40;
        const mesh::Surface lat_s = test::make_surface(SurfaceKind::Plane, 40 * a, 46 * a * std::sqrt(3.0) / 2);
        const auto lattice = mesh::triangulate_periodic(lattice_points(40, 46, a), lat_s);
        const auto hl = edge_orientation_histogram(lattice);
        CHECK(peak_ratio(hl) > 5.0);
        test::record_claim("5.1/5.2", "a lattice: three orientation peaks",
                           "largest 10° bin of the edge-orientation histogram / mean bin", peak_ratio(hl), "> 5");
        // All of a lattice's edges fall in the bins at 0°, 60° and 120°.
        const double sum = std::accumulate(hl.begin(), hl.end(), 0.0);
        CHECK((hl[0] + hl[6] + hl[12] + hl[5] + hl[11] + hl[17]) / sum > 0.99);
        // Without the radius jitter, repulsion drifts towards that lattice (§5.2.1).
        o.jitter = 0.0;
        o.max_iterations = 300;
        Rng rng3(4, RngStream::Sampling);
        const auto unjittered = mesh::triangulate_periodic(mesh::sample_periodic(s.period(), o, {}, rng3), s);
        CHECK(mesh::mesh_quality(unjittered).mean_min_angle_deg > mesh::mesh_quality(repelled).mean_min_angle_deg);
    }

    TEST_CASE("sampling: a spacing field sets the local density (density ∝ 1/s²)") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 1.0);
        Rng rng(9, RngStream::Sampling);
        mesh::SamplingOptions o;
        o.count = 2000;
        // Half the spacing on the left half: 4× the density there, so 4/5 of the points.
        const auto pts = mesh::sample_periodic(
            s.period(), o, [](const Vec2& d) { return d.x() < 0.5 ? 0.5 : 1.0; }, rng);
        const double left = double(std::count_if(pts.begin(), pts.end(), [](const Vec2& p) { return p.x() < 0.5; }));
        CHECK(left / 2000 == doctest::Approx(0.8).epsilon(0.06));
    }

    TEST_CASE("sampling: points stay on the sphere and avoid thin triangles there too") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Sphere, 2.0);
        Rng rng(2, RngStream::Sampling);
        mesh::SamplingOptions o;
        o.count = 1500;
        const auto pts = mesh::sample_sphere(2.0, o, {}, rng);
        for (const Vec3& p : pts)
            REQUIRE(p.norm() == doctest::Approx(2.0).epsilon(1e-12));
        const auto m = mesh::triangulate_sphere(pts, s);
        CHECK(mesh::mesh_quality(m).fraction_below_10deg < 0.002);
    }

    TEST_CASE("sampling: same seed gives identical points") {
        const mesh::Surface s = test::make_surface(SurfaceKind::Plane, 1.0, 0.5);
        mesh::SamplingOptions o;
        o.count = 500;
        Rng a(5, RngStream::Sampling), b(5, RngStream::Sampling), c(6, RngStream::Sampling);
        const auto pa = mesh::sample_periodic(s.period(), o, {}, a);
        const auto pb = mesh::sample_periodic(s.period(), o, {}, b);
        const auto pc = mesh::sample_periodic(s.period(), o, {}, c);
        CHECK(pa == pb);
        CHECK(pa != pc);
    }
}
