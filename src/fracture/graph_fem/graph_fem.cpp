/// @file run_graph_fem: the break loop (graph-fem digest §7.5) on the wedge layer, with Federl's driver
/// (one break per relaxation, §5.6.2; local relaxation, §5.8; the next break time in closed form).
#include "fracture/graph_fem/graph_fem.hpp"

#include "core/budget.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/toolkit/fem_loop.hpp"
#include "fracture/toolkit/pick.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;

namespace {

/// The faces and vertices an edge's break changes.
struct Around {
    std::vector<FaceId> faces;
    std::vector<std::size_t> vertices;
};

Around around(const sim::FemModel& model, const EdgeGraph::Edge& edge) {
    Around a;
    for (int i = 0; i < edge.sides; ++i) {
        const FaceId f = face_id(edge.side[static_cast<std::size_t>(i)].face);
        a.faces.push_back(f);
        for (mesh::VertexId v : model.mesh().faces[f].v)
            a.vertices.push_back(ix(v));
    }
    std::sort(a.vertices.begin(), a.vertices.end());
    a.vertices.erase(std::unique(a.vertices.begin(), a.vertices.end()), a.vertices.end());
    return a;
}

/// The crack wall a break opens: the dual edge (centroid → edge midpoint → centroid) × thickness (m²).
double crack_area(const sim::FemModel& model, const EdgeGraph::Edge& edge) {
    const mesh::SurfaceMesh& m = model.mesh();
    double length = 0, h = 0;
    for (int i = 0; i < edge.sides; ++i) {
        const EdgeGraph::Side& s = edge.side[static_cast<std::size_t>(i)];
        const auto p = m.face_positions(face_id(s.face));
        const auto k = static_cast<std::size_t>(s.edge);
        length += (0.5 * (p[k] + p[(k + 1) % 3]) - (p[0] + p[1] + p[2]) / 3.0).norm();
        const mesh::Face& face = m.faces[face_id(s.face)];
        h += 0.5 * (model.vertex_thickness(face.v[k]) + model.vertex_thickness(face.v[(k + 1) % 3])) / edge.sides;
    }
    return length * h;
}

/// The loop of run_graph_fem: the layer, its edge graph, stresses and criterion (made by
/// run_graph_fem), and the state the breaks carry from one to the next.
struct GraphFemLoop {
    sim::FemModel& model;
    const FractureOptions& options;
    const GraphFemOptions& graph_options;
    Rng& rng;
    const EdgeGraph& graph;
    StressCache& cache;
    EdgeCriterion& criterion;
    EventLog& events;
    FractureProgress& progress;
    RunStats& stats;
    GraphFemStats& g;
    const sim::LocalRelaxOptions local_options;
    const double radius0, dt_min, nu;
    double radius = radius0, rate_radius = radius0;
    std::vector<std::size_t> rate_seeds{};
    std::vector<std::uint32_t> changed{};
    // The ratio each edge must pass to be tried by stress: 1, or, for an edge whose break the
    // Griffith test turned down, the ratio at which it would pay. Released energy grows as the
    // load squared, so that is the trial's ratio × √(G_c·A / released): no futile retries.
    std::vector<double> level = std::vector<double>(graph.size(), 1.0);
    double shortfall = 1; ///< G_c·A / released of the last trial turned down

    /// One break: edge e, undone by the Griffith test when `gated` and the energy it releases
    /// (the strain lost at once plus what the relaxation releases) does not pay for the crack
    /// wall G_c·A. Updates the stresses and the criterion, logs the event; false when undone.
    bool try_break(std::size_t e, bool gated, const char* kind, double ratio) {
        const EdgeGraph::Edge& edge = graph.edge(e);
        const Around near = around(model, edge);
        const EdgeGraph::Side& side = edge.side[0];
        Event ev;
        ev.time = model.time();
        const auto p = model.mesh().face_positions(face_id(side.face));
        ev.position = 0.5 * (p[static_cast<std::size_t>(side.edge)] + p[static_cast<std::size_t>((side.edge + 1) % 3)]);
        ev.kind = kind;
        ev.ratio = ratio;
        Timer timer;
        double before = 0, released = 0;
        if (gated) {
            before = model.strain_energy(near.faces);
            model.begin_trial();
        }
        model.break_edges({{face_id(side.face), side.edge}});
        const double at_break = gated ? model.strain_energy(near.faces) : 0.0;
        stats.topology_seconds += timer.seconds();
        const std::size_t fallbacks = stats.local_fallbacks;
        const std::vector<std::size_t> moved = relax_after_change(model, near.vertices, radius, local_options, options,
                                                                  stats, rate_seeds, !gated, &released);
        // A local set that outgrew its share of the layer solved globally, which left no
        // residual anywhere: start the next one from the physical radius again. (The §5.8.3
        // check doubles the radius after each drift; without this, once past the fallback
        // size it never shrinks back, and every later break solves globally: bark at 16k
        // elements fell back on 4064 of 6185 breaks.)
        if (stats.local_fallbacks > fallbacks) radius = std::min(radius, radius0);
        if (gated) {
            double toughness = 0, young = 0;
            for (FaceId f : near.faces) {
                toughness += model.material(f).toughness / static_cast<double>(near.faces.size());
                young += model.material(f).young_modulus / static_cast<double>(near.faces.size());
            }
            const double gc = (1 - nu * nu) * toughness * toughness / young;
            const double paid = before - at_break + released, cost = gc * crack_area(model, edge);
            if (!(paid > cost)) {
                shortfall = paid > 0 ? std::max(cost / paid, 1.0) : 1e6;
                model.rollback();
                ++g.griffith_rejections;
                return false;
            }
            model.commit();
            check_drift(model, options, radius, stats);
        }
        timer.reset();
        for (FaceId f : near.faces)
            cache.refresh(ix(f)); // new material matrix: σ and σ̇ change in place
        cache.refresh_around(moved);
        if (gated) cache.refresh_around(model.last_updated_vertices()); // the §5.8.3 check's
        criterion.broke(e);
        if (cache.take_changes(changed))
            criterion.refresh_all();
        else
            criterion.refresh(changed);
        stats.stress_seconds += timer.seconds();
        ++g.breaks;
        events.add(ev, model);
        for (FaceId f : near.faces) // their energies changed: estimates made before are stale
            for (int k = 0; k < 3; ++k)
                level[graph.edge_of(ix(f), k)] = 1.0;
        return true;
    }

    bool touches_crack(std::size_t e) const {
        const EdgeGraph::Edge& edge = graph.edge(e);
        for (int i = 0; i < edge.sides; ++i)
            if (model.broken_edges(face_id(edge.side[static_cast<std::size_t>(i)].face)) != 0) return true;
        return false;
    }

    /// Griffith propagation (fem-split's Alg. 11 on the graph): from each crack tip a break made
    /// (a face it crossed with no other broken edge), the crack runs on through the tip face's
    /// most stressed other edge while the energy pays, whatever that edge's stress; a tip whose
    /// extension does not pay is arrested.
    void propagate(std::size_t from) {
        std::vector<std::size_t> front = {from};
        while (!front.empty()) {
            budget_check(); // a cascade can run thousands of breaks in one time step
            const std::size_t e = front.back();
            front.pop_back();
            const EdgeGraph::Edge& edge = graph.edge(e);
            for (int i = 0; i < edge.sides; ++i) {
                const std::uint32_t f = edge.side[static_cast<std::size_t>(i)].face;
                const unsigned broken = model.broken_edges(face_id(f));
                if (broken != 1u && broken != 2u && broken != 4u) continue; // not a tip
                std::size_t next = graph.size();
                double best_ratio = 0;
                for (int k = 0; k < 3; ++k) {
                    if ((broken >> k) & 1u) continue;
                    const std::size_t c = graph.edge_of(f, k);
                    if (criterion.ratio(c) > best_ratio) {
                        best_ratio = criterion.ratio(c);
                        next = c;
                    }
                }
                if (next == graph.size()) continue; // nothing pulls the tip open
                if (events.full(model.time())) return;
                if (try_break(next, true, "extend", best_ratio)) {
                    ++g.extensions;
                    front.push_back(next);
                } else {
                    ++g.arrests;
                    Event arrest;
                    arrest.time = model.time();
                    const EdgeGraph::Side& s = graph.edge(next).side[0];
                    const auto q = model.mesh().face_positions(face_id(s.face));
                    arrest.position =
                        0.5 * (q[static_cast<std::size_t>(s.edge)] + q[static_cast<std::size_t>((s.edge + 1) % 3)]);
                    arrest.kind = "arrest";
                    arrest.ratio = best_ratio;
                    g.arrests_at.push_back(arrest);
                    level[next] = std::max(level[next], best_ratio * std::sqrt(shortfall));
                }
            }
        }
    }

    /// No edge over its threshold: settle the time step and go to the next break, in closed form
    /// (every side's ratio is a + b·τ until K changes).
    void advance_to_next_break() {
        Timer timer;
        settle_time_step(model, cache, options, local_options, rate_radius, rate_seeds, stats);
        timer.reset();
        criterion.refresh_all(); // the rates changed where the step settled them
        cache.take_changes(changed);
        // The next break, in closed form: every side's ratio is a + b·τ until K changes.
        const double t0 = model.time();
        const double horizon = std::min(options.duration, model.stiffness_horizon());
        const double tau = criterion.next_crossing(level);
        // Just past the crossing, so the edge is over its threshold when the loop looks.
        const double t_next = std::isfinite(tau) ? std::min(horizon, t0 + tau + 0.5 * dt_min) : horizon;
        stats.stress_seconds += timer.seconds();
        advance_model(model, cache, t_next, stats);
        timer.reset();
        criterion.refresh_all();
        cache.take_changes(changed);
        stats.stress_seconds += timer.seconds();
    }

    /// Breaks until the duration or the event cap.
    void run() {
        while (true) {
            progress.update(model.time(), events.size());
            Timer timer;
            std::size_t picked = 0;
            double best = 0;
            // The edge most over its threshold (one break per relaxation), ties drawn from the seed:
            // equal-biaxial shrinkage ties every edge (digest §6.2).
            const bool have = pick_most_over(
                graph.size(), [&](std::size_t e) { return criterion.ratio(e); },
                [&](std::size_t e) { return criterion.ratio(e) > level[e] && !graph.broken(model, e); }, rng, picked,
                best);
            stats.stress_seconds += timer.seconds();
            if (have) {
                if (events.full(model.time())) break;
                if (!try_break(picked, graph_options.griffith && touches_crack(picked), "break", best)) {
                    level[picked] = best * std::sqrt(shortfall); // the Griffith gate: wait for the load
                    continue;
                }
                if (graph_options.griffith) propagate(picked);
                if (events.capped()) break;
                continue;
            }
            if (model.time() >= options.duration) break;

            advance_to_next_break();
        }
    }
};

} // namespace

CrackPattern run_graph_fem(sim::FemModel& model, const FractureOptions& options, const GraphFemOptions& graph_options,
                           Rng& rng, RunStats* stats_out, GraphFemStats* graph_out) {
    RunStats stats;
    GraphFemStats g;
    Timer total;
    EventLog events(options);
    const std::size_t elements_initial = model.num_alive();
    const EdgeGraph graph(model.mesh());
    g.edges = graph.size();
    g.nonzeros_initial = static_cast<std::size_t>(model.stiffness().nonZeros());

    sim::LocalRelaxOptions local_options;
    local_options.tolerance = options.local_tolerance;
    const double radius0 = initial_radius(model, local_options.tolerance);
    StressCache cache(model, false);
    relax_all(model, cache, stats); // the state at the start: equilibrium and its rate, globally
    stats.setup_seconds = total.seconds();
    EdgeCriterion criterion(model, cache, graph, graph_options.damage_radius);
    criterion.refresh_all();
    FractureProgress progress(options.duration, elements_initial);
    GraphFemLoop loop{model,
                      options,
                      graph_options,
                      rng,
                      graph,
                      cache,
                      criterion,
                      events,
                      progress,
                      stats,
                      g,
                      local_options,
                      radius0,
                      options.time_tolerance * options.duration,
                      model.poisson_ratio()};
    cache.take_changes(loop.changed);
    loop.run();
    progress.finish();

    g.nonzeros_final = static_cast<std::size_t>(model.stiffness().nonZeros());
    CrackPattern pattern = graph_pattern(model, graph, elements_initial);
    pattern.events_capped = events.capped();
    pattern.events = events.take();
    stats.total_seconds = total.seconds();
    if (stats_out) *stats_out = stats;
    if (graph_out) *graph_out = g;
    return pattern;
}

} // namespace crackle::fracture
