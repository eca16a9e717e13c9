/// @file fem-split's loop: relax/refresh, node picking, time step to the next fracture (Alg. 5), run (§5.7.4, §5.8).
#include "fracture/fem_split/splitter.hpp"

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/fem_split/nonlocal.hpp"
#include "fracture/toolkit/next_crossing.hpp"
#include "fracture/toolkit/pick.hpp"

#include <algorithm>
#include <string>

namespace crackle::fracture::split_detail {

std::vector<std::size_t> Splitter::relax_near(const std::vector<FaceId>& faces, double* released) {
    std::vector<std::size_t> seeds;
    for (FaceId f : faces)
        for (VertexId w : m_model.mesh().faces[f].v)
            seeds.push_back(ix(w));
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    // §5.8.3: no cascade of local relaxations may drift (a trial is checked once accepted).
    return relax_after_change(m_model, seeds, m_radius, m_local, m_options, m_stats, m_rate_seeds, !m_in_trial,
                              released);
}

Splitter::~Splitter() = default;

Splitter::Splitter(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng,
                   RunStats& stats, SplitStats& counts)
    : m_model(model), m_options(options), m_split(split), m_rng(rng), m_stats(stats), m_counts(counts),
      m_cache(model, false), m_events(options) {
    double h = 0;
    for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
        h += model.vertex_thickness(vertex_id(v));
    h /= static_cast<double>(std::max<std::size_t>(model.mesh().num_vertices(), 1));
    m_exclusion = split.exclusion_radius >= 0 ? split.exclusion_radius : h;
    m_smoothing =
        split.smoothing_radius >= 0 ? split.smoothing_radius : 1.5 * mesh::mesh_quality(model.mesh()).edge_mean;
    m_local.tolerance = options.local_tolerance;
    m_radius = initial_radius(model, m_local.tolerance);
    m_rate_radius = m_radius;
    make_nonlocal();
}

void Splitter::make_nonlocal() {
    if (m_split.initiation_length <= 0 && m_split.initiation_fraction <= 0) return;
    const double length = m_split.initiation_length, fraction = m_split.initiation_fraction;
    m_nonlocal = std::make_unique<NonlocalStress>(m_model, [this, length, fraction](std::size_t v) {
        return fraction > 0 ? fraction * m_model.vertex_thickness(vertex_id(v)) : length;
    });
}

double Splitter::nucleus_length(std::size_t v) const {
    return m_split.initiation_fraction > 0 ? m_split.initiation_fraction * m_model.vertex_thickness(vertex_id(v))
                                           : m_split.initiation_length;
}

NodalStress Splitter::node_stress(std::size_t v) const {
    auto cached = [&](std::size_t f) -> const sim::TopStress& { return m_cache.stress(f); };
    return m_nonlocal ? m_nonlocal->nodal(v, cached) : nodal_from(m_model, v, cached);
}

void Splitter::refresh_after(const std::vector<FaceId>& touched, const std::vector<std::size_t>& moved) {
    Timer timer;
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f));
    m_cache.refresh_around(moved);
    if (m_nonlocal) {
        // New and changed faces (cracks block the walks now): rebuild the neighbourhoods that
        // held them, and look at those nodes again.
        m_node_dirty.resize(m_model.mesh().num_vertices(), 1);
        for (std::size_t v : m_nonlocal->rebuild_around(touched))
            m_node_dirty[v] = 1;
    }
    m_stats.stress_seconds += timer.seconds();
}

void Splitter::check(const char* after) const {
    if (!m_split.check_invariants) return;
    const std::string problem = check_split_invariants(m_model);
    if (!problem.empty()) throw InvariantError(std::string("fem-split, after ") + after + ": " + problem);
}

bool Splitter::excluded(std::size_t v) const {
    const Vec3& p = m_model.mesh().positions[vertex_id(v)];
    for (const Vec3& z : m_zones)
        if (m_model.mesh().nearest_step(z, p).norm() < m_exclusion) return true;
    return false;
}

void Splitter::update_node_ratios() {
    // Only nodes of faces whose stress changed since the last pick need a new value.
    const std::size_t nv = m_model.mesh().num_vertices();
    std::vector<std::uint32_t> faces;
    const bool all = m_cache.take_changes(faces);
    m_node_ratio.resize(nv, 0.0);
    m_node_dirty.resize(nv, 1);
    if (all) std::fill(m_node_dirty.begin(), m_node_dirty.end(), 1);
    for (std::uint32_t f : faces)
        if (f < m_model.mesh().num_faces()) {
            for (VertexId w : m_model.mesh().faces[face_id(f)].v)
                m_node_dirty[ix(w)] = 1;
            if (m_nonlocal)
                for (std::uint32_t v : m_nonlocal->readers(f))
                    if (v < nv) m_node_dirty[v] = 1;
        }
    for (std::size_t v = 0; v < nv; ++v) {
        if (!m_node_dirty[v]) continue;
        m_node_dirty[v] = 0;
        m_node_ratio[v] = node_stress(v).ratio;
    }
}

bool Splitter::pick_node(std::size_t& node, double& ratio) {
    Timer timer;
    update_node_ratios();
    // Intact nodes and crack lips (a new crack may start at an old one's side); tips have their
    // own queue, and arrested ones their exclusion zones.
    const bool found = pick_most_over(
        m_model.mesh().num_vertices(), [&](std::size_t v) { return m_node_ratio[v]; },
        [&](std::size_t v) { return !m_model.incident_faces(v).empty() && !is_tip(m_model, v) && !excluded(v); }, m_rng,
        node, ratio);
    m_stats.stress_seconds += timer.seconds();
    return found;
}

void Splitter::advance_time() {
    Timer timer;
    settle_time_step(m_model, m_cache, m_options, m_local, m_rate_radius, m_rate_seeds, m_stats);

    // === Alg. 5 on nodal stresses: each node's in-surface ratio is convex in time along the
    // affine solution, so bracket the first crossing and bisect.
    timer.reset();
    const double t0 = m_model.time();
    const double horizon = std::min(m_options.duration, m_model.stiffness_horizon());
    const double dt_min = m_options.time_tolerance * m_options.duration;
    const std::size_t nv = m_model.mesh().num_vertices();
    // Each node's projected tensor is affine in time (the frame is held at t0 over the step):
    // T(t0 + τ) = T0 + τ·T1, so a probe costs a closed-form 2×2 eigenvalue per node.
    struct NodeLine {
        std::size_t v;
        Mat2 T0, T1;
        double threshold;
        mutable signed char eligible = -1; ///< not a tip that is not waiting, not excluded; −1: not asked yet
    };
    std::vector<NodeLine> lines;
    std::vector<char> dormant(nv, 0);
    for (std::size_t t : m_dormant)
        if (t < nv) dormant[t] = 1;
    // Waiting tips take part too: the step ends when one of them reaches the threshold. Asked
    // only of nodes over it at some probe (it walks the node's fan: 7 % of a 20000-element run
    // when asked of every node at every step).
    auto eligible = [&](const NodeLine& l) {
        if (l.eligible < 0) l.eligible = !((is_tip(m_model, l.v) && !dormant[l.v]) || excluded(l.v));
        return l.eligible == 1;
    };
    const Mat3 G = Mat3::Identity() + m_model.time() * m_model.growth().tensor();
    const Mat3 G_inv = G.inverse();
    for (std::size_t v = 0; v < nv; ++v) {
        if (m_model.incident_faces(v).empty()) continue;
        NodalStress means;
        Mat3 s0, s1;
        auto stress = [&](std::size_t f) -> const sim::TopStress& { return m_cache.stress(f); };
        auto rate = [&](std::size_t f) -> const sim::TopStress& { return m_cache.rate(f); };
        if (m_nonlocal) {
            if (!m_nonlocal->tensor(v, stress, s0, means)) continue;
            m_nonlocal->tensor(v, rate, s1, means);
        } else {
            if (!nodal_tensor(m_model, v, stress, s0, means)) continue;
            nodal_tensor(m_model, v, rate, s1, means);
        }
        const NodeFrame fr = node_frame(m_model, v, G, G_inv);
        lines.push_back({v, project(fr, s0), project(fr, s1), means.threshold});
    }
    auto over = [&](double t, std::vector<NodeLine>* which) {
        const double tau = t - t0;
        bool any = false;
        for (const NodeLine& l : lines)
            if (max_eigenvalue(l.T0 + tau * l.T1) > l.threshold && eligible(l)) {
                any = true;
                if (!which) return true;
                which->push_back(l);
            }
        return any;
    };
    const double t_next = next_crossing(
        t0, horizon, dt_min, m_last_step, [&](double t) { return over(t, nullptr); },
        [&](double t_hi) {
            std::vector<NodeLine> candidates;
            over(t_hi, &candidates);
            lines = std::move(candidates);
        });
    m_stats.stress_seconds += timer.seconds();
    advance_model(m_model, m_cache, t_next, m_stats);
}

EventLog& Splitter::run() {
    {
        Timer setup, timer;
        m_stats.solver_iterations += m_model.relax().iterations + m_model.solve_rate().iterations;
        m_stats.solves += 2;
        m_stats.solve_seconds += timer.seconds();
        timer.reset();
        m_cache.refresh_all();
        if (m_nonlocal) m_nonlocal->rebuild_all();
        m_stats.stress_seconds += timer.seconds();
        m_stats.setup_seconds = setup.seconds();
    }
    FractureProgress progress(m_options.duration, m_model.num_alive());
    while (true) {
        progress.update(m_model.time(), m_events.size());
        if (m_events.full(m_model.time())) break;
        // Tips first, first in first out (§5.7.4, Fig. 5.20).
        if (!m_tips.empty()) {
            const std::size_t tip = m_tips.front();
            m_tips.pop_front();
            Event ev;
            if (extend_tip(tip, ev)) m_events.add(ev, m_model);
            check("a crack-tip step");
            continue;
        }
        std::size_t node = 0;
        double ratio = 0;
        if (pick_node(node, ratio)) {
            Event ev;
            const Start started = start_fracture(node, ratio, ev);
            if (started == Start::Opened)
                m_events.add(ev, m_model);
            else if (started == Start::Blocked)
                m_zones.push_back(m_model.mesh().positions[vertex_id(node)]); // nowhere to cut
            check("a new fracture");
            continue;
        }
        if (m_model.time() >= m_options.duration) break;
        advance_time();
        // Tips that waited for the load look again, in the order they stopped.
        m_tips.insert(m_tips.end(), m_dormant.begin(), m_dormant.end());
        m_dormant.clear();
        refine_by_von_mises();
        check("von Mises refinement");
    }
    progress.finish();
    return m_events;
}

} // namespace crackle::fracture::split_detail
