#include "fracture/fem_split/fem_split.hpp"
#include "fracture/toolkit/fem_pattern.hpp"
#include "mesh/surface_mesh.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <numeric>

using namespace crackle;
using test::LayerSpec;

namespace {

/// A 0.2 m periodic plane, 1 cm thick, E = 1 GPa, threshold 0.1 MPa.
LayerSpec base_spec(std::uint64_t seed, std::size_t elements = 800) {
    LayerSpec s;
    s.size = Vec2(0.2, 0.2);
    s.elements = elements;
    s.seed = seed;
    return s;
}

double mean(const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

/// One side (face, edge) of the edge p→q or q→p, found through p's faces.
std::pair<mesh::FaceId, int> find_edge(const sim::FemModel& model, std::size_t p, std::size_t q) {
    for (std::uint32_t f : model.incident_faces(p)) {
        const mesh::Face& face = model.mesh().faces[mesh::face_id(f)];
        for (int k = 0; k < 3; ++k) {
            const std::size_t a = mesh::ix(face.v[static_cast<std::size_t>(k)]);
            const std::size_t b = mesh::ix(face.v[static_cast<std::size_t>((k + 1) % 3)]);
            if ((a == p && b == q) || (a == q && b == p)) return {mesh::face_id(f), k};
        }
    }
    FAIL("no edge between ", p, " and ", q);
    return {mesh::NO_FACE, -1};
}

/// A loaded layer with a crack two edges long cut through it (split an edge in the middle,
/// then open a → m → b): the scripted change the topology tests share.
/// `size`: the tile's side; the cylinder is a tile that long around, the sphere one of the same
/// area.
struct CutLayer {
    explicit CutLayer(std::uint64_t seed, std::size_t elements = 400, double size = 0.2,
                      mesh::SurfaceKind kind = mesh::SurfaceKind::Plane)
        : layer([&] {
              LayerSpec s = base_spec(seed, elements);
              s.kind = kind;
              s.size =
                  kind == mesh::SurfaceKind::Sphere ? Vec2::Constant(size / (2 * std::sqrt(PI))) : Vec2(size, size);
              s.growth = {sim::GrowthKind::Isogonic, 2e-4, 2e-4, 0};
              return s;
          }()) {
        layer.model->set_time(0.5);
        layer.model->relax();
    }
    /// Splits the edge the crack will open (a → m → b); returns m.
    std::size_t split() {
        sim::FemModel& m = *layer.model;
        const mesh::Face f0 = m.mesh().faces[mesh::face_id(0)];
        a = mesh::ix(f0.v[0]);
        b = mesh::ix(f0.v[1]);
        mv = mesh::ix(m.split_edge(mesh::face_id(0), 0, 0.5).first);
        return mv;
    }
    /// Splits and cuts; returns the vertices whose faces changed.
    std::vector<std::size_t> cut() {
        split();
        return open();
    }
    /// Opens the split edge's two halves.
    std::vector<std::size_t> open() {
        sim::FemModel& m = *layer.model;
        const auto copies = m.cut({find_edge(m, a, mv), find_edge(m, mv, b)});
        CHECK(copies.size() == 1); // the middle vertex opens; a and b stay the slit's tips
        std::vector<std::size_t> seeds{a, b, mv};
        for (const auto& [copy, origin] : copies)
            seeds.push_back(mesh::ix(copy));
        return seeds;
    }
    test::Layer layer;
    std::size_t a = 0, b = 0, mv = 0;
};

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("fem-split: a rolled-back cut and refinement restore the model exactly, on every surface") {
        for (mesh::SurfaceKind kind :
             {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder, mesh::SurfaceKind::Sphere}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            CutLayer c(1, 400, 0.2, kind);
            sim::FemModel& m = *c.layer.model;
            const sim::FemModel before = m;
            m.begin_trial();
            auto seeds = c.cut();
            // A local refinement too, as the tip sub-model of §5.7.8 makes and discards.
            for (mesh::FaceId f : m.subdivide(mesh::face_id(7)))
                for (mesh::VertexId w : m.mesh().faces[f].v)
                    seeds.push_back(mesh::ix(w));
            double radius = 4;
            m.relax_local(seeds, radius);
            CHECK(m.mesh().num_vertices() > before.mesh().num_vertices());
            m.rollback();

            REQUIRE(m.mesh().num_vertices() == before.mesh().num_vertices());
            REQUIRE(m.mesh().num_faces() == before.mesh().num_faces());
            CHECK(m.mesh().validate().empty());
            for (std::size_t f = 0; f < m.mesh().num_faces(); ++f) {
                const auto& x = m.mesh().faces[mesh::face_id(f)];
                const auto& y = before.mesh().faces[mesh::face_id(f)];
                CHECK(x.v == y.v);
                CHECK(x.offset == y.offset);
                for (int k = 0; k < 3; ++k)
                    CHECK(m.mesh().neighbor(mesh::face_id(f), k).face
                          == before.mesh().neighbor(mesh::face_id(f), k).face);
            }
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v) {
                CHECK(m.mesh().positions[mesh::vertex_id(v)] == before.mesh().positions[mesh::vertex_id(v)]);
                CHECK(m.top_position(mesh::vertex_id(v)) == before.top_position(mesh::vertex_id(v)));
                CHECK(m.incident_faces(v) == before.incident_faces(v));
            }
            CHECK(m.strain_energy() == before.strain_energy());
            // The stiffness too: the same relaxation from a perturbed state lands on the same nodes.
            sim::FemModel again = before;
            m.set_time(0.6);
            again.set_time(0.6);
            m.relax();
            again.relax();
            double worst = 0, scale = 0;
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v) {
                worst = std::max(worst,
                                 (m.top_position(mesh::vertex_id(v)) - again.top_position(mesh::vertex_id(v))).norm());
                scale = std::max(
                    scale, (again.top_position(mesh::vertex_id(v)) - before.top_position(mesh::vertex_id(v))).norm());
            }
            CHECK(scale > 0);
            CHECK(worst <= 1e-9 * scale);
        }
    }

    TEST_CASE("fem-split: a cut keeps the strain energy, its relaxation releases exactly ½ rᵀΔx of it, and the edge "
              "split before it releases next to nothing, on every surface") {
        for (mesh::SurfaceKind kind :
             {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder, mesh::SurfaceKind::Sphere}) {
            std::vector<double> share;
            for (std::size_t elements : {400u, 1600u}) {
                CAPTURE(std::string(mesh::to_string(kind)));
                CAPTURE(elements);
                CutLayer c(2, elements, 0.2, kind);
                sim::FemModel& m = *c.layer.model;
                // The split node starts at its rest position plus the interpolated displacement:
                // on the plane that is the equilibrium; on a curved surface the finer facets
                // move it a little (the discretisation converging), not by a misfit.
                c.split();
                const sim::SolveStats split = m.relax();
                const double e0 = m.strain_energy();
                c.open();
                const double e1 = m.strain_energy();
                CHECK(e1 == doctest::Approx(e0).epsilon(1e-12)); // nodes duplicated in place
                const sim::SolveStats s = m.relax();
                const double e2 = m.strain_energy();
                CHECK(e2 < e1);
                CHECK(s.energy_release == doctest::Approx(e1 - e2).epsilon(1e-6));
                CHECK(fracture::check_split_invariants(m).empty());
                share.push_back(split.energy_release / s.energy_release);
                CHECK(share.back() < 0.03); // R ≈ 5 edges at 400 elements: measured 1.3 % (cylinder), 2.2 % (sphere)
                if (kind == mesh::SurfaceKind::Plane) CHECK(share.back() < 1e-9);
                test::record_claim("Alg. 11",
                                   std::string("energy released by relaxing a cut = strain-energy drop (")
                                       + mesh::to_string(kind) + ", " + std::to_string(elements) + " elements)",
                                   "|½ rᵀΔx / (E₁ − E₂) − 1|", std::abs(s.energy_release / (e1 - e2) - 1), "< 1e-6");
                test::record_claim("Alg. 11",
                                   std::string("an edge split releases next to nothing next to the cut (")
                                       + mesh::to_string(kind) + ", " + std::to_string(elements) + " elements)",
                                   "split's release / cut's release", share.back(), "< 0.03");
            }
            if (kind != mesh::SurfaceKind::Plane) CHECK(share[1] < 0.5 * share[0]); // and less on finer meshes
        }
    }

    TEST_CASE("fem-split: local relaxation after a cut reaches the global solution, on every surface") {
        for (mesh::SurfaceKind kind :
             {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder, mesh::SurfaceKind::Sphere}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            // A tile wide enough that the relaxed set (about 5 decay lengths 1.6h for a 1e-2
            // force tolerance, docs/perf-limits.md) stays local.
            CutLayer c(3, 3000, 0.5, kind);
            c.split(); // on curved surfaces the split's own small release is not the cut's (test above)
            c.layer.model->relax();
            const sim::FemModel before = *c.layer.model;
            const auto seeds = c.open();
            sim::FemModel global = *c.layer.model;
            sim::FemModel& local = *c.layer.model;
            double radius = 2;
            const sim::SolveStats s = local.relax_local(seeds, radius);
            global.relax();
            CHECK(s.nodes < local.mesh().num_vertices()); // it did stay local
            double worst = 0, moved = 0;
            for (std::size_t v = 0; v < global.mesh().num_vertices(); ++v) {
                const Vec3 g = global.top_position(mesh::vertex_id(v));
                worst = std::max(worst, (local.top_position(mesh::vertex_id(v)) - g).norm());
                if (v < before.mesh().num_vertices())
                    moved = std::max(moved, (g - before.top_position(mesh::vertex_id(v))).norm());
            }
            CAPTURE(worst);
            CAPTURE(moved);
            CHECK(moved > 0);
            CHECK(worst < 1e-2 * moved); // the force tolerance is 1e-2 of the change
            test::record_claim("5.25",
                               std::string("local relaxation after one cut equals the global solve (")
                                   + mesh::to_string(kind) + ")",
                               "largest position error / largest displacement the cut caused", worst / moved, "< 1e-2");
        }
    }

    TEST_CASE("fem-split: tips extend first in first out, both ends of a new crack in turn (Fig. 5.20)") {
        for (std::uint64_t seed : {1u, 2u}) {
            LayerSpec s = base_spec(seed);
            s.growth = {sim::GrowthKind::Anisotropic, 3e-4, 0.0, 0.0}; // stretch along x: cracks along y
            s.toughness = 1;                                           // tips run while they release any energy
            const auto r = test::run_split(s);
            REQUIRE(r.pattern.events.size() > 6);
            const auto& ev = r.pattern.events;
            REQUIRE(ev[0].kind == "split");
            // The first crack: its extensions alternate between the two ends while both live.
            const Vec3 p = ev[0].position;
            Vec3 d = Vec3::Zero();
            std::vector<int> sides;
            for (std::size_t i = 1; i < ev.size() && ev[i].kind == "extend" && sides.size() < 4; ++i) {
                Vec3 q = ev[i].position - p;
                for (int k = 0; k < 2; ++k) // nearest periodic image
                    q[k] -= 0.2 * std::round(q[k] / 0.2);
                if (d == Vec3::Zero()) d = q.normalized();
                sides.push_back(q.dot(d) > 0 ? 1 : -1);
            }
            CAPTURE(seed);
            REQUIRE(sides.size() == 4);
            CHECK(sides[0] == 1);
            CHECK(sides[1] == -1);
            CHECK(sides[2] == 1);
            CHECK(sides[3] == -1);
            CHECK(r.split.splits > 0);
            CHECK(r.split.extensions > r.split.splits); // cracks run on from their start
            int alternations = 0;
            for (std::size_t i = 1; i < sides.size(); ++i)
                alternations += sides[i] != sides[i - 1];
            test::record_claim("5.20", "tips of a new crack extend first in first out, the two ends in turn",
                               "side changes among the first 4 extensions (seed " + std::to_string(seed) + ")",
                               alternations, "= 3");
        }
    }

    TEST_CASE("fem-split: Griffith arrest: cracks start where the layer is stiff and every tip stops where the energy "
              "released no longer pays for the crack wall, on plane and cylinder, at every resolution (Fig. 5.21)") {
        // E peaks along the middle line v = ½ (1.8 GPa) and falls to 0.2 GPa at v = 0 and 1
        // (a tent, continuous across the periodic seam); a uniform stretch across v loads the
        // stiff middle most, so cracks start there and run both ways along v. A channel crack
        // releases G ∝ E·ε²·h, and the wall costs G_IC = (1 − ν²)K²/E, so a tip stops where
        // E·ε = const: with ε = r·t, E(tip)·t(arrest) is the same for every tip, whatever
        // its crack's start time, mesh or surface.
        auto tent = std::make_shared<GrayImage>();
        tent->width = 1;
        tent->height = 64;
        for (int j = 0; j < 64; ++j)
            tent->pixels.push_back(float(1.0 - std::abs(2.0 * (j + 0.5) / 64 - 1.0)));
        auto spec = [&](mesh::SurfaceKind kind, std::size_t elements_per_0_04_m2, double toughness) {
            LayerSpec s = base_spec(1);
            s.kind = kind;
            // The cylinder's circumference 0.6 m (R = 9.5 cm, about 10 layer thicknesses).
            s.size = kind == mesh::SurfaceKind::Plane ? Vec2(0.2, 0.2) : Vec2(0.6, 0.2);
            s.elements = elements_per_0_04_m2 * (kind == mesh::SurfaceKind::Plane ? 1 : 3);
            s.growth = {sim::GrowthKind::Anisotropic, 8e-5, 0.0, 0.0}; // stretch across v (around the trunk)
            s.toughness = toughness;
            s.young_variation.pattern = sim::PatternKind::Image;
            s.young_variation.image = tent;
            s.young_variation.amplitude = 0.8;
            return s;
        };
        std::map<std::pair<int, std::size_t>, double> balance; // (surface, resolution) → mean E·t
        for (mesh::SurfaceKind kind : {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder})
            for (std::size_t elements : {800u, 1600u}) {
                const LayerSpec s = spec(kind, elements, 6000);
                test::Layer layer(s);
                fracture::FractureOptions o;
                fracture::SplitOptions split;
                split.check_invariants = true;
                Rng rng(s.seed, RngStream::Fracture);
                fracture::SplitStats run;
                const auto pattern = fracture::run_fem_split(*layer.model, o, split, rng, nullptr, &run);
                CAPTURE(std::string(mesh::to_string(kind)));
                CAPTURE(elements);
                REQUIRE(run.splits >= 4);
                REQUIRE(run.arrests_at.size() >= 8);
                for (const auto& e : pattern.events)
                    if (e.kind == "split") CHECK(std::abs(layer.surface.uv(e.position).y() - 0.5) < 0.05);
                std::vector<double> c;
                double weakest = INFINITY;
                for (const auto& a : run.arrests_at) {
                    const double E = layer.young.at(a.position, layer.surface.uv(a.position));
                    c.push_back(E * a.time);
                    weakest = std::min(weakest, E);
                }
                const double m = mean(c);
                double worst = 0, var = 0;
                for (double x : c) {
                    worst = std::max(worst, std::abs(x / m - 1));
                    var += sqr(x / m - 1);
                }
                const double spread = std::sqrt(var / double(c.size()));
                CAPTURE(m);
                CAPTURE(worst);
                CAPTURE(spread);
                CHECK(spread < 0.12); // every tip on the same balance...
                CHECK(worst < 0.3);
                CHECK(weakest > 0.5e9); // ...so no tip reaches the weak side (0.2 GPa)
                balance[{int(kind), elements}] = m;
                test::record_claim("5.21",
                                   std::string("Griffith arrest per tip, ") + mesh::to_string(kind) + ", "
                                       + std::to_string(s.elements) + " elements",
                                   "spread (rms, relative) of E(tip)·t(arrest) over " + std::to_string(c.size())
                                       + " tips",
                                   spread, "< 0.12");
            }
        // Independent of the element size (Ch. 6) and of the surface.
        const double plane = balance[{int(mesh::SurfaceKind::Plane), 800}];
        const double plane_fine = balance[{int(mesh::SurfaceKind::Plane), 1600}];
        const double cyl = balance[{int(mesh::SurfaceKind::Cylinder), 800}];
        const double cyl_fine = balance[{int(mesh::SurfaceKind::Cylinder), 1600}];
        CHECK(plane_fine == doctest::Approx(plane).epsilon(0.08));
        CHECK(cyl_fine == doctest::Approx(cyl).epsilon(0.08));
        CHECK(cyl == doctest::Approx(plane).epsilon(0.15));
        test::record_claim("5.21", "Griffith arrest independent of the element size (plane, 800 vs 1600 elements)",
                           "relative change of the mean E(tip)·t(arrest)", std::abs(plane_fine / plane - 1), "< 0.08");
        test::record_claim("5.21", "Griffith arrest independent of the element size (cylinder, 2400 vs 4800)",
                           "relative change of the mean E(tip)·t(arrest)", std::abs(cyl_fine / cyl - 1), "< 0.08");
        test::record_claim("5.21", "Griffith arrest: cylinder (R = 10 h) against plane",
                           "relative difference of the mean E(tip)·t(arrest)", std::abs(cyl / plane - 1), "< 0.15");
        // With a negligible toughness the same cracks run through the weak side.
        const LayerSpec brittle = spec(mesh::SurfaceKind::Plane, 800, 1);
        const auto free_run = test::run_split(brittle);
        CHECK(free_run.split.arrests == 0);
        double lowest = 1;
        for (const auto& e : free_run.pattern.events) {
            const double v = brittle.size.y() > 0 ? e.position.y() / brittle.size.y() : 0;
            lowest = std::min(lowest, std::min(v, 1 - v));
        }
        CHECK(lowest < 0.05);
    }

    TEST_CASE("fem-split: cuts leave no triangle below the minimum angle (edge collapse §5.7.5 and smoothing §5.7.9)") {
        LayerSpec s = base_spec(4);
        s.shrinkage = {3e-4, 3e-4};
        test::Layer probe(s);
        const double initial = mesh::mesh_quality(probe.model->mesh()).min_angle_deg;
        for (double smoothing : {0.0, -1.0}) {
            fracture::SplitOptions split;
            split.smoothing_radius = smoothing; // -1: angle-based smoothing near new tips (§5.7.9)
            const auto r = test::run_split(s, 1.0, split);
            CAPTURE(smoothing);
            REQUIRE(r.split.splits > 5);
            CHECK(r.split.collapses > 0);
            CHECK((r.split.smoothed > 0) == (smoothing != 0.0)); // and every move kept the invariants
            CHECK(r.split.flips > 0);                            // slivers near cuts flipped away
            // A split leaves ≥ min_angle; a collapse may go down to half of it; snapping adds none;
            // a flip only raises the worst angle of its two faces.
            CAPTURE(initial);
            CHECK(r.stats.min_angle_deg >= std::min(initial, 0.5 * split.min_angle_deg) - 1e-9);
            test::record_claim("5.22/5.23",
                               std::string("edge collapse and flips leave no sliver (")
                                   + (smoothing != 0.0 ? "with" : "without") + " §5.7.9 smoothing)",
                               "worst triangle angle after the run (deg; initial mesh " + std::to_string(initial) + ")",
                               r.stats.min_angle_deg, ">= min(initial, 6)");
        }
    }

    TEST_CASE("fem-split: drying mud meets mostly at T-junctions, and isogonic growth is isotropic (Figs. 5.27-5.28)") {
        std::vector<double> t, y, a;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            LayerSpec mud = base_spec(seed);
            mud.shrinkage = {3e-4, 3e-4};
            const auto m = test::run_split(mud);
            CAPTURE(seed);
            CHECK(m.stats.fragments > 10);
            // Fragment labels agree across every intact edge.
            const mesh::SurfaceMesh& pm = m.pattern.mesh;
            std::size_t disagree = 0;
            for (std::size_t f = 0; f < pm.num_faces(); ++f)
                for (int k = 0; k < 3; ++k) {
                    const mesh::FaceNeighbor nb = pm.neighbor(mesh::face_id(f), k);
                    if (nb.face != mesh::NO_FACE && m.pattern.fragment[f] != m.pattern.fragment[mesh::ix(nb.face)])
                        ++disagree;
                }
            CHECK(disagree == 0);
            CHECK(m.stats.junctions > 20);
            t.push_back(m.stats.t_junction_fraction);
            y.push_back(m.stats.y_junction_fraction);
            LayerSpec iso = base_spec(seed);
            iso.growth = {sim::GrowthKind::Isogonic, 3e-4, 3e-4, 0};
            const auto g = test::run_split(iso);
            CHECK(g.stats.anisotropy < 0.2);
            a.push_back(g.stats.anisotropy);
        }
        CHECK(mean(t) > 2 * mean(y));
        CHECK(mean(a) < 0.1);
        test::record_claim("5.28", "mud: T-junctions outnumber Y-junctions (fem-split, 3 seeds)",
                           "T-junction fraction / Y-junction fraction", mean(t) / std::max(mean(y), 1e-9), "> 2");
        test::record_claim("5.27", "isogonic growth gives an isotropic network (fem-split, 3 seeds)", "mean anisotropy",
                           mean(a), "< 0.1");
    }

    TEST_CASE(
        "fem-split: crack statistics change little between two refinement levels (unlike mass-spring, Fig. 4.9)") {
        std::vector<double> coarse, fine, area_c, area_f;
        for (std::uint64_t seed : {1u, 2u}) {
            LayerSpec s = base_spec(seed, 600);
            s.shrinkage = {3e-4, 3e-4};
            const auto c = test::run_split(s);
            s.elements = 2400; // edges half as long
            const auto f = test::run_split(s);
            coarse.push_back(c.stats.crack_length_per_area);
            fine.push_back(f.stats.crack_length_per_area);
            area_c.push_back(c.stats.mean_fragment_area);
            area_f.push_back(f.stats.mean_fragment_area);
        }
        const double length_ratio = mean(fine) / mean(coarse), area_ratio = mean(area_f) / mean(area_c);
        CAPTURE(length_ratio);
        CAPTURE(area_ratio);
        CHECK(length_ratio > 0.85);
        CHECK(length_ratio < 1.15);
        test::record_claim("4.9", "fem-split: crack density independent of resolution (600 vs 2400 elements)",
                           "ρ_c(2400) / ρ_c(600)", length_ratio, "in [0.85, 1.15]");
        CHECK(area_ratio > 0.7);
        CHECK(area_ratio < 1.4);
    }

    TEST_CASE("fem-split: crack length and fragments grow monotonically through one run, later cracks end on earlier "
              "ones, the run is reproducible (Fig. 5.30)") {
        LayerSpec s = base_spec(5);
        s.shrinkage = {3e-4, 3e-4};
        // Snapshots of one run, at every time step.
        std::vector<fracture::PatternStatistics> snaps;
        fracture::FractureOptions o;
        o.hooks.before_time_step = [&](const sim::FemModel& m) {
            snaps.push_back(fracture::pattern_statistics(fracture::pattern_from_model(m, "fem-split", 0)));
        };
        const auto r = test::run_split(s, 1.0, {}, o);
        REQUIRE(snaps.size() > 5);
        snaps.push_back(r.stats);
        std::size_t grew = 0;
        for (std::size_t i = 1; i < snaps.size(); ++i) {
            CAPTURE(i);
            CHECK(snaps[i].crack_length >= snaps[i - 1].crack_length);
            CHECK(snaps[i].fragments >= snaps[i - 1].fragments);
            grew += snaps[i].crack_length > snaps[i - 1].crack_length;
        }
        CHECK(grew > 3); // a sequence, not one burst
        test::record_claim("5.30", "crack length and fragments grow monotonically through one run",
                           "time steps at which the crack length grew (none shrank)", grew, "> 3");
        CHECK(r.stats.fragments > 5);
        // Hierarchical: cracks that start later meet the earlier ones at right angles.
        CHECK(r.stats.t_junction_fraction > 2 * r.stats.y_junction_fraction);
        test::record_claim("5.30", "later cracks end on earlier ones",
                           "T-junction fraction (Y: " + std::to_string(r.stats.y_junction_fraction) + ")",
                           r.stats.t_junction_fraction, "> 2 × Y");
        for (std::size_t i = 1; i < r.pattern.events.size(); ++i)
            CHECK(r.pattern.events[i].time >= r.pattern.events[i - 1].time);
        const auto b = test::run_split(s);
        REQUIRE(r.pattern.events.size() == b.pattern.events.size());
        for (std::size_t i = 0; i < r.pattern.events.size(); ++i) {
            CHECK(r.pattern.events[i].time == b.pattern.events[i].time);
            CHECK(r.pattern.events[i].position == b.pattern.events[i].position);
        }
    }

    TEST_CASE("fem-split: local and global relaxation give the same pattern statistics") {
        LayerSpec s = base_spec(6, 600);
        s.shrinkage = {3e-4, 3e-4};
        fracture::FractureOptions global;
        global.local_relaxation = false;
        const auto l = test::run_split(s);
        const auto g = test::run_split(s, 1.0, {}, global);
        CAPTURE(l.stats.fragments);
        CAPTURE(g.stats.fragments);
        CHECK(l.stats.crack_length_per_area == doctest::Approx(g.stats.crack_length_per_area).epsilon(0.1));
        CHECK(double(l.stats.fragments) == doctest::Approx(double(g.stats.fragments)).epsilon(0.2));
    }

    TEST_CASE("fem-split: refinement around tips (§5.7.6) from a coarse mesh matches a uniform fine one") {
        LayerSpec s = base_spec(7, 150);
        s.shrinkage = {3e-4, 3e-4};
        fracture::FractureOptions o;
        o.min_element_size = 0.012;
        const auto adaptive = test::run_split(s, 1.0, {}, o);
        CHECK(adaptive.split.subdivisions > 0);
        s.elements = 1000;
        const auto uniform = test::run_split(s);
        CAPTURE(adaptive.stats.crack_length_per_area);
        CAPTURE(uniform.stats.crack_length_per_area);
        CHECK(adaptive.stats.crack_length_per_area
              == doctest::Approx(uniform.stats.crack_length_per_area).epsilon(0.2));
    }

    TEST_CASE("fem-split: von Mises refinement (§5.7.7) subdivides where elements disagree, down to the size limit") {
        // Stiffness varying across the tile: neighbouring elements report different stresses.
        LayerSpec s = base_spec(9, 200);
        s.growth = {sim::GrowthKind::Isogonic, 2e-4, 2e-4, 0};
        s.young_variation.pattern = sim::PatternKind::Noise;
        s.young_variation.amplitude = 0.5;
        s.young_variation.scale = 0.05;
        fracture::FractureOptions o;
        o.min_element_size = 0.015;
        fracture::SplitOptions split;
        split.vm_threshold = 0.05;
        const auto with = test::run_split(s, 1.0, split, o);
        CHECK(with.split.vm_refinements > 0);
        CHECK(with.split.splits > 0);
        split.vm_threshold = 0;
        const auto without = test::run_split(s, 1.0, split, o);
        CHECK(without.split.vm_refinements == 0);
        // The refined run cracks like the unrefined one, not into a different pattern.
        CHECK(with.stats.crack_length_per_area == doctest::Approx(without.stats.crack_length_per_area).epsilon(0.3));
    }

    TEST_CASE("fem-split: tip directions from a temporary refined sub-model (§5.7.8) keep cracks across the stretch") {
        std::vector<double> with, without;
        for (std::uint64_t seed : {1u, 3u, 5u}) {
            LayerSpec s = base_spec(seed, 300); // coarse: about 1.5 cm edges on a 1 cm layer
            s.growth = {sim::GrowthKind::Anisotropic, 3e-4, 0.0, 0.0};
            s.toughness = 1;
            fracture::SplitOptions split;
            split.tip_submodel_levels = 2;
            const auto sub = test::run_split(s, 1.0, split); // invariants checked after every step
            const auto plain = test::run_split(s);
            CAPTURE(seed);
            CHECK(sub.split.submodels > 0);
            CHECK(sub.stats.anisotropy > 0.9); // cracks run along y, across the stretch
            double d = std::abs(sub.stats.dominant_angle_deg - 90.0);
            CHECK(std::min(d, 180.0 - d) < 10.0);
            with.push_back(sub.stats.crack_length_per_area);
            without.push_back(plain.stats.crack_length_per_area);
        }
        // The finer tip stress turns the cracks a little more (measured: 17 % more crack
        // length over 5 seeds, anisotropy 0.95 against 0.98), but it is the same pattern.
        CHECK(mean(with) == doctest::Approx(mean(without)).epsilon(0.25));
    }

    TEST_CASE("fem-split: drying mud on a cylinder and a sphere meets at T-junctions like on the plane, with the "
              "mesh valid after every step") {
        std::map<int, double> density, t_share;
        for (mesh::SurfaceKind kind :
             {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder, mesh::SurfaceKind::Sphere}) {
            std::vector<double> t, y, rho;
            for (std::uint64_t seed : {1u, 2u}) {
                LayerSpec s = base_spec(seed, 800);
                s.kind = kind;
                s.size = kind == mesh::SurfaceKind::Sphere ? Vec2(0.06, 0.06) : Vec2(0.2, 0.2);
                s.shrinkage = {3e-4, 3e-4};
                const auto r = test::run_split(s); // invariants checked after every topology change
                CAPTURE(std::string(mesh::to_string(kind)));
                CAPTURE(seed);
                CHECK(r.stats.fragments > 10);
                CHECK(r.stats.junctions > 20);
                t.push_back(r.stats.t_junction_fraction);
                y.push_back(r.stats.y_junction_fraction);
                rho.push_back(r.stats.crack_length_per_area);
            }
            CAPTURE(std::string(mesh::to_string(kind)));
            CHECK(mean(t) > 2 * mean(y));
            density[int(kind)] = mean(rho);
            t_share[int(kind)] = mean(t);
        }
        // The T share, junctions counted with hanging-node splits merged (fracture/hanging_splits.hpp):
        const double t_plane = t_share[int(mesh::SurfaceKind::Plane)];
        MESSAGE("T share: plane " << t_plane << ", cylinder " << t_share[int(mesh::SurfaceKind::Cylinder)]
                                  << ", sphere " << t_share[int(mesh::SurfaceKind::Sphere)]);
        // Measured 0.578 / 0.614 / 0.593 (2 seeds, 800 elements): curvature leaves the share alone.
        CHECK(t_share[int(mesh::SurfaceKind::Cylinder)] == doctest::Approx(t_plane).epsilon(0.2));
        CHECK(t_share[int(mesh::SurfaceKind::Sphere)] == doctest::Approx(t_plane).epsilon(0.2));
        // Curvature changes the density little: R = 3.2 h (cylinder), 6 h (sphere).
        const double plane = density[int(mesh::SurfaceKind::Plane)];
        MESSAGE("crack length per area: plane " << plane << ", cylinder " << density[int(mesh::SurfaceKind::Cylinder)]
                                                << ", sphere " << density[int(mesh::SurfaceKind::Sphere)]);
        CHECK(density[int(mesh::SurfaceKind::Cylinder)] == doctest::Approx(plane).epsilon(0.15));
        CHECK(density[int(mesh::SurfaceKind::Sphere)] == doctest::Approx(plane).epsilon(0.15));
    }
}
