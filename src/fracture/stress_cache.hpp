#pragma once
/// @file Top-face stresses of every element of a wedge-FEM layer, cached and moved along the
/// affine-in-time solution (shared by the FEM fracture methods).

#include "core/timer.hpp"
#include "fracture/fem_remove.hpp"
#include "sim/fem_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace crackle::fracture {

/// Top-face stresses of every element, affine in time while the stiffness is fixed:
/// σ(t₀ + τ) = σ₀ + τ·σ̇. Keeps each element's ratio at the current time and the set of
/// over-threshold candidates, so an event costs work only where stresses changed.
class StressCache {
public:
    /// `ratios`: keep each element's ratio (fem-remove picks elements by it; fem-split, which
    /// works on nodes, does not need them).
    explicit StressCache(const sim::FemModel& model, bool ratios = true) : m_model(model), m_ratios(ratios) {}

    void resize() {
        const std::size_t n = m_model.mesh().num_faces();
        m_s0.resize(n);
        m_rate.resize(n);
        m_ratio.resize(n, 0.0);
    }

    void refresh(std::size_t f, bool rate = true) {
        m_changed.push_back(static_cast<std::uint32_t>(f));
        if (!m_model.alive(mesh::face_id(f))) {
            m_ratio[f] = 0.0;
            return;
        }
        m_s0[f] = m_model.top_stress(mesh::face_id(f));
        if (rate) m_rate[f] = m_model.top_stress_rate(mesh::face_id(f));
        if (m_ratios) m_ratio[f] = ratio_at(f, 0.0);
    }

    void refresh_rate(std::size_t f) {
        if (m_model.alive(mesh::face_id(f))) m_rate[f] = m_model.top_stress_rate(mesh::face_id(f));
    }

    void refresh_all() {
        m_all_changed = true;
        resize();
        for (std::size_t f = 0; f < m_s0.size(); ++f)
            refresh(f);
    }

    /// Re-evaluates the elements around the given vertices (§5.8.4: recompute stresses only
    /// where nodes moved), skipping those whose nodes moved too little to change their stress
    /// by 1e-7 of the threshold. `rates` re-evaluates σ̇ instead of σ.
    std::size_t refresh_around(const std::vector<std::size_t>& vertices, bool rates = false) {
        const auto& update = m_model.last_update();
        std::size_t count = 0;
        ++m_stamp;
        if (m_seen.size() < m_s0.size()) m_seen.resize(m_s0.size(), 0);
        for (std::size_t v : vertices) {
            for (std::uint32_t f : m_model.incident_faces(v)) {
                if (m_seen[f] == m_stamp || !m_model.alive(mesh::face_id(f))) continue;
                m_seen[f] = m_stamp;
                const mesh::Face& face = m_model.mesh().faces[mesh::face_id(f)];
                const double moved =
                    std::max({update[mesh::ix(face.v[0])], update[mesh::ix(face.v[1])], update[mesh::ix(face.v[2])]});
                const auto& mat = m_model.material(mesh::face_id(f));
                // A rate change is judged over the whole run (time scale 1).
                if (mat.young_modulus * moved < 1e-7 * mat.threshold_stress * m_model.element_size(mesh::face_id(f)))
                    continue;
                if (rates)
                    refresh_rate(f);
                else
                    refresh(f, false);
                ++count;
            }
        }
        return count;
    }

    /// Moves every cached stress forward by dt along its rate.
    void advance(double dt) {
        m_all_changed = true;
        for (std::size_t f = 0; f < m_s0.size(); ++f) {
            if (!m_model.alive(mesh::face_id(f))) continue;
            for (std::size_t k = 0; k < 3; ++k)
                m_s0[f][k] += dt * m_rate[f][k];
            if (m_ratios) m_ratio[f] = ratio_at(f, 0.0);
        }
    }

    /// Largest top principal stress over threshold, dt after the cache's time.
    double ratio_at(std::size_t f, double dt) const {
        double best = -std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < 3; ++k) {
            const sim::wedge::Vec6 s = dt == 0.0 ? m_s0[f][k] : sim::wedge::Vec6(m_s0[f][k] + dt * m_rate[f][k]);
            best = std::max(best, sim::wedge::max_principal(s).value);
        }
        return best / m_model.material(mesh::face_id(f)).threshold_stress;
    }

    double ratio(std::size_t f) const { return m_ratio[f]; }
    const sim::TopStress& stress(std::size_t f) const { return m_s0[f]; }
    const sim::TopStress& rate(std::size_t f) const { return m_rate[f]; }
    /// Takes another cache's values (a snapshot of the same model).
    void assign_from(const StressCache& other) {
        m_s0 = other.m_s0;
        m_rate = other.m_rate;
        m_ratio = other.m_ratio;
    }

    /// (lower bound of the time until the element can reach its threshold, element), sorted.
    std::vector<std::pair<double, std::size_t>> earliest_crossings() const {
        auto frobenius = [](const sim::wedge::Vec6& v) {
            return std::sqrt(sqr(v[0]) + sqr(v[1]) + sqr(v[2]) + 2 * (sqr(v[3]) + sqr(v[4]) + sqr(v[5])));
        };
        std::vector<std::pair<double, std::size_t>> out;
        out.reserve(m_s0.size());
        for (std::size_t f = 0; f < m_s0.size(); ++f) {
            if (!m_model.alive(mesh::face_id(f))) continue;
            const double thr = m_model.material(mesh::face_id(f)).threshold_stress;
            double bound = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < 3; ++k) {
                const double s = frobenius(m_s0[f][k]), r = frobenius(m_rate[f][k]);
                if (s >= thr)
                    bound = 0.0;
                else if (r > 0)
                    bound = std::min(bound, (thr - s) / r);
            }
            if (std::isfinite(bound)) out.emplace_back(bound, f);
        }
        std::sort(out.begin(), out.end());
        return out;
    }
    std::size_t size() const { return m_s0.size(); }

    /// The faces whose stress (not rate) changed since the last call; true if all may have.
    bool take_changes(std::vector<std::uint32_t>& faces) {
        faces.swap(m_changed);
        m_changed.clear();
        const bool all = m_all_changed;
        m_all_changed = false;
        return all;
    }

private:
    const sim::FemModel& m_model;
    bool m_ratios = true;

    std::vector<sim::TopStress> m_s0, m_rate;
    std::vector<double> m_ratio;
    std::vector<std::uint32_t> m_seen;
    std::vector<std::uint32_t> m_changed;
    bool m_all_changed = true;
    std::uint32_t m_stamp = 0;
};

} // namespace crackle::fracture

namespace crackle::fracture {

/// Hops that cover ln(1/tol)·1.6 mean thicknesses (the decay length of a local change, §5.8).
inline double initial_radius(const sim::FemModel& model, double tolerance) {
    double h = 0;
    for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
        h += model.vertex_thickness(mesh::vertex_id(v));
    h /= static_cast<double>(std::max<std::size_t>(model.mesh().num_vertices(), 1));
    const double edge = mesh::mesh_quality(model.mesh()).edge_mean;
    return std::clamp(std::ceil(1.6 * std::log(1.0 / tolerance) * h / edge), 2.0, 64.0);
}

/// Moves the model to t along the exact affine solution and the cache with it; only when
/// shrinkage rebuilt the stiffness does it re-solve and re-evaluate every stress.
inline void advance_model(sim::FemModel& model, StressCache& cache, double t, RunStats& stats) {
    Timer timer;
    const double t0 = model.time();
    const std::size_t builds = model.stiffness_builds();
    model.advance_time(t);
    ++stats.time_steps;
    stats.stiffness_rebuilds += model.stiffness_builds() - builds;
    if (model.stiffness_changed()) {
        stats.solver_iterations += model.relax().iterations + model.solve_rate().iterations;
        stats.solves += 2;
        stats.solve_seconds += timer.seconds();
        timer.reset();
        cache.refresh_all(); // new B matrices: every stress changes
    } else {
        stats.solve_seconds += timer.seconds();
        timer.reset();
        cache.advance(t - t0);
    }
    stats.stress_seconds += timer.seconds();
}

/// §5.8.3, after a local relaxation: relaxes globally when the residual left anywhere exceeds
/// FractureOptions::drift_tolerance of a threshold-level nodal force, and then doubles the
/// local radius (the thesis' ρ increase). Returns whether it did (every node moved).
inline bool check_drift(sim::FemModel& model, const FractureOptions& options, double& radius, RunStats& stats) {
    if (!options.local_relaxation) return false;
    Timer timer;
    const bool over = model.max_residual_force() > options.drift_tolerance * model.force_scale();
    if (over) {
        stats.solver_iterations += model.relax().iterations;
        ++stats.solves;
        ++stats.drift_relaxations;
        radius = std::min(2.0 * radius, 256.0);
    }
    stats.solve_seconds += timer.seconds();
    return over;
}

/// Once per time step (§5.8): settles the rate solution around `rate_seeds` (the vertices whose
/// elements changed since the last step; cleared), then relaxes globally when the local
/// relaxations have left forces that could shift a stress by 1e-3 of a threshold (the thesis
/// relaxes globally every time step). Refreshes the cache where needed; times go to `stats`.
inline void settle_time_step(sim::FemModel& model, StressCache& cache, const FractureOptions& options,
                             const sim::LocalRelaxOptions& local, double& rate_radius,
                             std::vector<std::size_t>& rate_seeds, RunStats& stats) {
    Timer timer;
    if (!rate_seeds.empty()) {
        std::sort(rate_seeds.begin(), rate_seeds.end());
        rate_seeds.erase(std::unique(rate_seeds.begin(), rate_seeds.end()), rate_seeds.end());
        // Seeds of rolled-back changes may name vertices that no longer exist.
        while (!rate_seeds.empty() && rate_seeds.back() >= model.mesh().num_vertices())
            rate_seeds.pop_back();
        sim::SolveStats s =
            options.local_relaxation ? model.relax_rate_local(rate_seeds, rate_radius, local) : model.solve_rate();
        stats.solver_iterations += s.iterations;
        ++stats.solves;
        // §5.8.3 for the rate, which Alg. 5's next fracture time rests on.
        if (options.local_relaxation
            && model.max_rate_residual_force()
                   > options.drift_tolerance * model.force_scale() / std::max(options.duration, 1e-300)) {
            s = model.solve_rate();
            stats.solver_iterations += s.iterations;
            ++stats.solves;
            ++stats.drift_relaxations;
            rate_radius = std::min(2.0 * rate_radius, 256.0);
        }
        stats.solve_seconds += timer.seconds();
        timer.reset();
        cache.refresh_around(model.last_updated_vertices(), true);
        stats.stress_seconds += timer.seconds();
        rate_seeds.clear();
    }
    timer.reset();
    if (options.local_relaxation && model.max_residual_force() > 1e-3 * model.force_scale()) {
        stats.solver_iterations += model.relax().iterations + model.solve_rate().iterations;
        stats.solves += 2;
        stats.global_cleanups += 1;
        stats.solve_seconds += timer.seconds();
        timer.reset();
        cache.refresh_all();
        stats.stress_seconds += timer.seconds();
    } else {
        stats.solve_seconds += timer.seconds();
    }
    if (options.before_time_step) options.before_time_step(model);
}

} // namespace crackle::fracture
