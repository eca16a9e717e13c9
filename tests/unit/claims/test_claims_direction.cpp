// Thesis claim of Figs. 5.22-5.23 about single fem-split events: a crack runs along the
// computed principal plane; moving a vertex onto the plane (edge collapse) keeps it there,
// and only snapping to a vertex that cannot move (the plane-rotation fallback) turns it.

#include "core/log.hpp"
#include "fracture/fem_split/fem_split.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace crackle;
using test::LayerSpec;

namespace {

/// Silences the warning each capped run logs (the runs below stop after one event on purpose).
struct QuietLog {
    QuietLog() : saved(log::level()) { log::set_level(log::Level::Error); }
    ~QuietLog() { log::set_level(saved); }
    QuietLog(const QuietLog&) = delete;
    QuietLog& operator=(const QuietLog&) = delete;
    log::Level saved;
};

/// Angle between two undirected lines (degrees, [0, 90]).
double line_angle(const Vec2& a, const Vec2& b) {
    return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * RAD_TO_DEG;
}

/// Crack edges at the vertices of reference position p: (vertex, other end) for every border
/// edge of a face around a vertex at p, with the edge's unrolled direction.
struct CrackEdgeAt {
    std::size_t vertex, other;
    Vec2 direction;
};
std::vector<CrackEdgeAt> crack_edges_at(const sim::FemModel& m, const Vec3& p) {
    std::vector<CrackEdgeAt> out;
    const mesh::SurfaceMesh& mesh = m.mesh();
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
        if (mesh.positions[mesh::vertex_id(v)] != p) continue;
        for (std::uint32_t f : m.incident_faces(v)) {
            const mesh::FaceId fid = mesh::face_id(f);
            if (!m.alive(fid)) continue;
            for (int k = 0; k < 3; ++k) {
                if (mesh.neighbor(fid, k).face != mesh::NO_FACE) continue;
                const std::size_t a = mesh::ix(mesh.faces[fid].v[static_cast<std::size_t>(k)]);
                const std::size_t b = mesh::ix(mesh.faces[fid].v[static_cast<std::size_t>((k + 1) % 3)]);
                if (a != v && b != v) continue;
                const int kv = a == v ? k : (k + 1) % 3, ko = a == v ? (k + 1) % 3 : k;
                out.push_back({v, a == v ? b : a, mesh.corner_domain(fid, ko) - mesh.corner_domain(fid, kv)});
            }
        }
    }
    return out;
}

/// True if some crack edge at p in `edges` runs along `d` (an edge that existed before).
bool has_direction(const std::vector<CrackEdgeAt>& edges, const Vec2& d) {
    return std::any_of(edges.begin(), edges.end(), [&](const CrackEdgeAt& e) {
        return (e.direction - d).norm() < 1e-12 * std::max(1.0, d.norm());
    });
}

/// Runs fem-split on `m` from its current state until its `events`-th event (a fresh run: no
/// tips queued, so its first event is a new fracture); returns that event and the run's stats.
bool one_event(sim::FemModel& m, std::uint64_t seed, std::size_t events, fracture::Event& ev,
               fracture::SplitStats* stats = nullptr) {
    fracture::FractureOptions o;
    o.duration = 1.0;
    o.max_events = events;
    fracture::SplitOptions split;
    split.check_invariants = true;
    Rng rng(seed, RngStream::Fracture);
    const fracture::CrackPattern p = fracture::run_fem_split(m, o, split, rng, nullptr, stats);
    if (p.events.size() < events) return false;
    ev = p.events.back();
    return true;
}

/// The node a new fracture at reference position p started from: of the vertices there (a crack
/// lip has copies), the one with the highest stress ratio, as fem-split picks it.
std::size_t start_node(const sim::FemModel& m, const Vec3& p) {
    std::size_t node = m.mesh().num_vertices();
    double best = -1;
    for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
        if (m.mesh().positions[mesh::vertex_id(v)] == p && !m.incident_faces(v).empty()) {
            const double r = fracture::nodal_stress(m, v).ratio;
            if (r > best) {
                best = r;
                node = v;
            }
        }
    return node;
}

/// Angles (degrees) between the crack edges at p in `after` that are not in `before` and d.
std::vector<double> new_edge_angles(const sim::FemModel& before, const sim::FemModel& after, const Vec3& p,
                                    const Vec2& d) {
    std::vector<double> angles;
    auto known = crack_edges_at(before, p);
    for (const CrackEdgeAt& e : crack_edges_at(after, p)) {
        if (has_direction(known, e.direction)) continue; // an old edge, or the other lip of a new one
        known.push_back(e);
        angles.push_back(line_angle(e.direction, d));
    }
    return angles;
}

/// Outcome of one event: the angles of its new crack edges and the cuts that snapped to a vertex.
struct Cuts {
    std::vector<double> angles;
    std::size_t snaps = 0;
};

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("claims 5.22, 5.23: cracks run along the computed principal direction, only snapped cuts turn") {
        // A drying layer (anisotropic shrinkage, Young's modulus perturbed by ±30 % noise, so the
        // principal directions vary) is cracked one event at a time. Before each event the
        // state is reconstructed (the model at the event's time, relaxed) and the in-surface
        // principal direction computed at the node (new fracture) or tip (extension) the event
        // started from; each new crack edge is compared with it. A cut through an edge lands on
        // the plane, and so does an edge collapse (the vertex moves onto the plane, §5.7.5);
        // only a snap to a vertex that cannot move leaves it. So every deviation must be
        // explained by a snap, and most cuts must follow the plane exactly.
        QuietLog quiet;
        constexpr double EXACT_DEG = 0.01;
        std::vector<Cuts> events;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            LayerSpec s;
            s.size = Vec2(0.2, 0.2);
            s.elements = 600;
            s.seed = seed;
            s.shrinkage = {3e-4, 1.5e-4};
            s.toughness = 1;
            s.young_variation.pattern = sim::PatternKind::Noise;
            s.young_variation.amplitude = 0.3;
            test::Layer layer(s);
            sim::FemModel& m = *layer.model;
            for (int step = 0; step < 10; ++step) {
                CAPTURE(seed);
                CAPTURE(step);
                const sim::FemModel m0 = m;
                fracture::Event ev;
                fracture::SplitStats one, two;
                if (!one_event(m, seed, 1, ev, &one)) break;
                REQUIRE(ev.kind == "split");
                // === The new fracture: direction at its node just before the cut
                sim::FemModel pre = m0;
                pre.set_time(ev.time);
                pre.relax();
                const std::size_t node = start_node(pre, ev.position);
                REQUIRE(node < pre.mesh().num_vertices());
                const fracture::NodalStress ns = fracture::nodal_stress(pre, node);
                CHECK(ns.ratio == doctest::Approx(ev.ratio).epsilon(1e-3)); // the same state
                events.push_back({new_edge_angles(m0, m, ev.position, Vec2(ns.crack.x(), ns.crack.y())), one.snaps});
                CHECK(!events.back().angles.empty());

                // === The next event of a run that goes on from m0: a tip extension, from m's state
                sim::FemModel longer = m0;
                fracture::Event ev2;
                if (!one_event(longer, seed, 2, ev2, &two) || ev2.kind != "extend") continue;
                sim::FemModel at = m;
                at.relax();
                Cuts ext{{}, two.snaps - one.snaps}; // (an upper bound: rejected trials count too)
                auto known = crack_edges_at(m, ev2.position);
                for (const CrackEdgeAt& e : crack_edges_at(longer, ev2.position)) {
                    if (has_direction(known, e.direction)) continue;
                    known.push_back(e);
                    // The new edge's far end is the tip it grew from, a vertex of m too.
                    const Vec3 tip_p = longer.mesh().positions[mesh::vertex_id(e.other)];
                    std::size_t tip = m.mesh().num_vertices();
                    for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
                        if (m.mesh().positions[mesh::vertex_id(v)] == tip_p) tip = v;
                    REQUIRE(tip < m.mesh().num_vertices());
                    const fracture::NodalStress nt = fracture::nodal_stress(at, tip);
                    ext.angles.push_back(line_angle(e.direction, Vec2(nt.crack.x(), nt.crack.y())));
                }
                if (!ext.angles.empty()) events.push_back(ext);
            }
        }
        std::vector<double> all;
        std::size_t unexplained = 0;
        for (const Cuts& c : events) {
            std::size_t off = 0;
            for (double a : c.angles) {
                all.push_back(a);
                off += a > EXACT_DEG;
            }
            unexplained += off > c.snaps;
        }
        REQUIRE(all.size() >= 60);
        std::sort(all.begin(), all.end());
        const double exact_share =
            double(std::count_if(all.begin(), all.end(), [&](double a) { return a <= EXACT_DEG; }))
            / double(all.size());
        const double p90 = all[all.size() * 9 / 10];
        test::record_claim("5.22", "the crack angle equals the computed principal direction",
                           "new crack edges measured (new fractures and tip extensions, 3 seeds)", double(all.size()),
                           ">= 60");
        test::record_claim("5.22", "the crack angle equals the computed principal direction",
                           "events with more turned cuts (> 0.01 deg) than snaps to a vertex", double(unexplained),
                           "== 0");
        test::record_claim("5.22", "the crack angle equals the computed principal direction",
                           "share of cuts within 0.01 deg of the principal plane", exact_share, ">= 0.8");
        test::record_claim("5.22", "the crack angle equals the computed principal direction",
                           "90th percentile of |cut - principal plane| (deg)", p90, "< 0.01");
        test::record_claim("5.23", "snapping to a vertex turns the crack (plane rotation)",
                           "largest |cut - principal plane| over all cuts (deg)", all.back(), "< 35");
        CAPTURE(all.size());
        CHECK(unexplained == 0);
        CHECK(exact_share >= 0.8);
        CHECK(p90 < EXACT_DEG);
        CHECK(all.back() < 35.0);
    }
}
