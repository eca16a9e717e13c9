// graph-fem (graph-fem digest §5.4, §6.2, §7.5–7.8): analytic first breaks, the closed-form break
// time, statistics over seeds, and its pattern contract, on the plane, the cylinder and the sphere.
#include "fracture/graph_fem/graph_fem.hpp"
#include "fracture/mass_spring/mass_spring.hpp"
#include "fracture/toolkit/next_crossing.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

using namespace crackle;
using mesh::SurfaceKind;
using test::Layer;
using test::LayerSpec;

namespace {

fracture::GraphFemOptions stress_only() {
    fracture::GraphFemOptions o;
    o.griffith = false;
    return o;
}

/// The first event of a graph-fem run, and the model as it left it.
struct FirstBreak {
    double time = -1;
    Vec3 position = Vec3::Zero();
};

FirstBreak first_break(const LayerSpec& spec, double duration) {
    fracture::FractureOptions o;
    o.max_events = 1;
    const auto r = test::run_graph(spec, duration, stress_only(), o);
    FirstBreak b;
    if (!r.pattern.events.empty()) {
        b.time = r.pattern.events.front().time;
        b.position = r.pattern.events.front().position;
    }
    return b;
}

/// The largest cos² between an edge of the mesh and direction d (the best-aligned edge).
double best_cos2(const mesh::SurfaceMesh& m, const Vec3& d) {
    double best = 0;
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
        const auto p = m.face_positions(mesh::face_id(f));
        for (std::size_t k = 0; k < 3; ++k)
            best = std::max(best, sqr((p[(k + 1) % 3] - p[k]).normalized().dot(d)));
    }
    return best;
}

double mean(const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

LayerSpec mud(std::uint64_t seed, std::size_t elements = 800) {
    LayerSpec s;
    s.size = Vec2(0.2, 0.2);
    s.elements = elements;
    s.young = 1e7;
    s.threshold = 2e4;
    s.toughness = 50;
    s.shrinkage = {0.006, 0.002};
    s.threshold_variation.pattern = sim::PatternKind::Noise;
    s.threshold_variation.amplitude = 0.15;
    s.threshold_variation.scale = 0.05;
    s.seed = seed;
    return s;
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("graph-fem: a bar in tension first breaks its best-aligned edge at sigma_th / cos^2 (digest 5.4)") {
        // ν = 0: the bonded layer stretched along u carries the uniaxial stress E·r·t exactly, so
        // the edge at angle θ to u sees E·r·t·cos²θ and the best-aligned one breaks first.
        LayerSpec s;
        s.poisson = 0.0;
        s.elements = 400;
        s.growth = {sim::GrowthKind::Anisotropic, 1e-3, 0.0, 0.0};
        s.fem.tolerance = 1e-12;
        const Layer layer(s);
        const double c2 = best_cos2(layer.model->mesh(), Vec3::UnitX());
        const double predicted = s.threshold / (s.young * 1e-3 * c2);
        const FirstBreak b = first_break(s, 2 * predicted);
        CAPTURE(c2);
        CHECK(std::abs(b.time / predicted - 1) < 1e-6);
        test::record_claim("graph-fem bar", "first break at sigma_th/cos^2 theta_min", "time / predicted",
                           b.time / predicted, "1e-6");
        // ν = 0.3: the layer is held across (ε_v = 0), so σ_vv = ν σ_uu and the edge that
        // maximises cos²θ + ν sin²θ goes first, at σ_uu = E ε/(1 − ν²).
        s.poisson = 0.3;
        const Layer layer2(s);
        const double best = 0.3 + 0.7 * best_cos2(layer2.model->mesh(), Vec3::UnitX());
        const double predicted2 = s.threshold * (1 - 0.09) / (s.young * 1e-3 * best);
        CHECK(std::abs(first_break(s, 2 * predicted2).time / predicted2 - 1) < 1e-6);
    }

    TEST_CASE("graph-fem: a bonded, uniformly shrinking layer starts cracking at eps = sigma_th (1 - nu) / E "
              "on the plane, the cylinder and the sphere") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(mesh::to_string(kind));
            LayerSpec s;
            s.kind = kind;
            // Curved layers 1 mm thick on radii near 10 cm (h/R ≈ 0.01), where the thin-film
            // answer holds to O(h/R).
            s.size =
                kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(kind == SurfaceKind::Cylinder ? 0.6 : 0.2, 0.2);
            s.thickness = kind == SurfaceKind::Plane ? 0.01 : 0.001;
            s.elements = kind == SurfaceKind::Plane ? 400 : 1500;
            s.shrinkage = {0.01, 0.01};
            s.fem.stiffness_refresh = 0.0;
            s.fem.tolerance = 1e-12;
            const double eps = s.threshold * (1 - s.poisson) / s.young;
            const double predicted = eps / (0.01 * (1 + eps)); // ε = st / (1 − st)
            const FirstBreak b = first_break(s, 2 * predicted);
            // The plane to the small-strain linearisation (O(ε) ≈ 1e-4); on the curved surfaces the
            // thin-shell stress differs by O(h/R) more.
            const double tolerance = kind == SurfaceKind::Plane ? 1e-3 : 0.02;
            CHECK(std::abs(b.time / predicted - 1) < tolerance);
            test::record_claim("graph-fem onset",
                               std::string("first crack at eps = sigma_th(1-nu)/E, ") + mesh::to_string(kind),
                               "strain / predicted", b.time / predicted, kind == SurfaceKind::Plane ? "0.1 %" : "2 %");
        }
    }

    TEST_CASE("graph-fem: the closed-form next break time equals Alg. 5's bisection on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(mesh::to_string(kind));
            LayerSpec s = mud(2, 400);
            s.kind = kind;
            s.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.2, 0.2);
            if (kind == SurfaceKind::Cylinder) s.growth = {sim::GrowthKind::Anisotropic, 0.003, 0.0, 0.0};
            Layer layer(s);
            sim::FemModel& m = *layer.model;
            m.relax();
            m.solve_rate();
            fracture::StressCache cache(m, false);
            cache.refresh_all();
            const fracture::EdgeGraph graph(m.mesh());
            fracture::EdgeCriterion criterion(m, cache, graph, 0.0);
            criterion.refresh_all();
            std::size_t which = 0;
            const double tau = criterion.next_crossing({}, &which);
            REQUIRE(std::isfinite(tau));
            double step = 1e-3;
            const double dt_min = 1e-12;
            const double bisected = fracture::next_crossing(
                0.0, 10.0, dt_min, step,
                [&](double t) {
                    for (std::size_t e = 0; e < graph.size(); ++e)
                        if (criterion.ratio_at(e, t) > 1.0) return true;
                    return false;
                },
                [](double) {});
            CHECK(std::abs(bisected - tau) <= 2 * dt_min);
            CHECK(std::abs(criterion.ratio_at(which, tau) - 1) < 1e-12);
            // And the model moved there agrees: the cached rates are the real ones.
            m.advance_time(tau);
            cache.refresh_all();
            criterion.refresh_all();
            CHECK(std::abs(criterion.ratio(which) - 1) < 1e-6);
        }
    }

    TEST_CASE("graph-fem: runs on every surface with a fixed system, finite output and the same bytes twice") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            for (bool griffith : {true, false}) {
                CAPTURE(mesh::to_string(kind));
                CAPTURE(griffith);
                LayerSpec s = mud(3, 500);
                s.kind = kind;
                s.size = kind == SurfaceKind::Sphere ? Vec2(0.06, 0.06) : Vec2(0.2, 0.2);
                fracture::GraphFemOptions o;
                o.griffith = griffith;
                const auto a = test::run_graph(s, 1.0, o);
                const auto b = test::run_graph(s, 1.0, o);
                CHECK(a.graph.breaks > 10);
                CHECK(a.graph.nonzeros_final == a.graph.nonzeros_initial);
                CHECK(a.pattern.mesh.validate() == "");
                REQUIRE(a.pattern.events.size() == b.pattern.events.size());
                for (std::size_t i = 0; i < a.pattern.events.size(); ++i) {
                    CHECK(a.pattern.events[i].time == b.pattern.events[i].time);
                    CHECK(a.pattern.events[i].position == b.pattern.events[i].position);
                }
                REQUIRE(a.pattern.deformed.size() == b.pattern.deformed.size());
                for (std::size_t v = 0; v < a.pattern.deformed.size(); ++v) {
                    CHECK(a.pattern.deformed[v].allFinite());
                    CHECK(a.pattern.deformed[v] == b.pattern.deformed[v]);
                }
                // Every broken edge is drawn: two dual segments, each with two lips.
                CHECK(a.pattern.cracks.size() <= 4 * a.graph.breaks);
                CHECK(a.pattern.cracks.size() > 2 * a.graph.breaks);
                for (const auto& c : a.pattern.cracks)
                    CHECK((std::isfinite(c.opening) && c.opening >= 0));
            }
        }
    }

    TEST_CASE("graph-fem: mud cracks isotropically over five seeds, and a fully cracked layer falls into plates") {
        std::vector<double> anisotropy, psi6;
        for (std::uint64_t seed = 1; seed <= 5; ++seed) {
            const auto r = test::run_graph(mud(seed));
            CAPTURE(seed);
            CHECK(r.stats.fragments > 10);
            anisotropy.push_back(r.stats.anisotropy);
            psi6.push_back(r.stats.psi6);
        }
        CHECK(mean(anisotropy) < 0.1);
        CHECK(mean(psi6) < 0.15);
        test::record_claim("graph-fem mud", "isotropic on a random mesh (5 seeds)", "mean anisotropy", mean(anisotropy),
                           "< 0.1");
    }

    TEST_CASE("graph-fem: growth along u opens cracks perpendicular to it, on the plane and around a trunk") {
        LayerSpec s = mud(1);
        s.shrinkage = {};
        s.growth = {sim::GrowthKind::Anisotropic, 0.006, 0.0, 0.0};
        const auto r = test::run_graph(s);
        CHECK(r.stats.anisotropy > 0.4);
        CHECK(std::abs(r.stats.dominant_angle_deg - 90.0) < 15.0);
        // Bark: the trunk grows around its axis (u), so the fissures run along it (v).
        s.kind = SurfaceKind::Cylinder;
        s.size = Vec2(0.3, 0.2);
        const auto bark = test::run_graph(s);
        CHECK(bark.stats.anisotropy > 0.4);
        CHECK(bark.stats.axial_fraction > 0.6);
    }

    TEST_CASE("graph-fem: on a regular lattice every crack follows the lattice (mesh locking)") {
        // The limitation the docs state: cracks run on the dual, so a regular mesh leaves them
        // the lattice's directions only, whatever the load. Crossing a face a crack runs along
        // the third edge's direction (0°, 60°, 120°), at tips and junctions along a median (30°,
        // 90°, 150°): together a 12-fold order, ψ12 = |Σ ℓ e^{12iθ}| / Σ ℓ ≈ 1 (ψ6 of the two
        // families cancels in part).
        auto psi12 = [](const fracture::CrackPattern& p) {
            double re = 0, im = 0, total = 0;
            for (const auto& seg : fracture::crack_segments(p)) {
                const double len = seg.weight * seg.length(), th = std::atan2((seg.b - seg.a).y(), (seg.b - seg.a).x());
                re += len * std::cos(12 * th);
                im += len * std::sin(12 * th);
                total += len;
            }
            return total > 0 ? std::hypot(re, im) / total : 0.0;
        };
        LayerSpec spec = mud(1);
        const mesh::Surface surface = test::make_surface(SurfaceKind::Plane, 0.2, 0.2);
        Rng sampling(1, RngStream::Sampling);
        const mesh::SurfaceMesh lattice =
            fracture::mass_spring_mesh(surface, 400, fracture::Lattice::Regular, mesh::SamplingOptions{}, sampling);
        Layer layer(spec); // fields only; the model below uses the lattice
        sim::LayerFields fields{&layer.thickness, &layer.young, &layer.threshold, &layer.toughness, spec.poisson};
        sim::FemModel model(lattice, surface, sim::GrowthField(spec.growth, SurfaceKind::Plane), spec.shrinkage, fields,
                            spec.fem);
        Rng rng(1, RngStream::Fracture);
        const fracture::CrackPattern p = fracture::run_graph_fem(model, {}, {}, rng);
        CHECK(fracture::pattern_statistics(p).crack_length > 0);
        CHECK(psi12(p) > 0.9);
        // The random mesh of the same scene is not locked.
        const auto r = test::run_graph(spec);
        CHECK(psi12(r.pattern) < 0.3);
        CHECK(r.stats.psi6 < 0.3);
    }

    TEST_CASE("graph-fem: Griffith tips run while the energy pays and arrest where it does not") {
        // The same scene at two toughnesses: cheap crack walls let tips run far from where they
        // started (many extensions per stress-driven break), dear ones stop them (arrests), and
        // without the test no tip runs below threshold at all.
        LayerSpec s = mud(5, 600);
        s.toughness = 20;
        const auto cheap = test::run_graph(s);
        s.toughness = 2000;
        const auto dear = test::run_graph(s);
        const auto none = test::run_graph(s, 1.0, stress_only());
        CHECK(cheap.graph.extensions > cheap.graph.breaks / 2);
        CHECK(dear.graph.arrests > 0);
        CHECK(dear.graph.extensions < cheap.graph.extensions / 2);
        CHECK(none.graph.extensions == 0);
        CHECK(none.graph.griffith_rejections == 0);
        CHECK(cheap.stats.fragments > 5);
    }

    TEST_CASE("graph-fem: mud statistics against fem-split at equal and twice the element count") {
        // Differences stated, not hidden (docs/benchmarks.md has the full table): graph-fem's
        // dual cracks are longer (they zig-zag at element scale) and its junctions read as Y at
        // the scale of one element; fragments and crack density agree within a factor of two.
        for (std::size_t elements : {800u, 1600u}) {
            CAPTURE(elements);
            const auto g = test::run_graph(mud(4, elements));
            fracture::SplitOptions split;
            const auto f = test::run_split(mud(4, elements), 1.0, split, {}, false);
            const double ratio = g.stats.crack_length_per_area / f.stats.crack_length_per_area;
            CHECK(ratio > 0.7);
            CHECK(ratio < 2.0);
            CHECK(g.stats.fragments > f.stats.fragments / 2);
            CHECK(g.stats.fragments < f.stats.fragments * 2);
            CHECK(g.stats.anisotropy < 0.15);
        }
    }
}
