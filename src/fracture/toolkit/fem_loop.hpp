#pragma once
/// @file The steps both FEM fracture loops take around their events (§5.6.2, §5.8): the local
/// relaxation after a change and its accounting, the §5.8.3 residual check, moving along the
/// affine solution to the next time, and settling each time step.

#include "core/timer.hpp"
#include "fracture/run.hpp"
#include "fracture/toolkit/stress_cache.hpp"
#include "sim/fem_model.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

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

/// Solves the equilibrium and its rate globally and re-evaluates every cached stress: the start
/// of a run, and whenever the whole stiffness changed.
inline void relax_all(sim::FemModel& model, StressCache& cache, RunStats& stats) {
    Timer timer;
    stats.solver_iterations += model.relax().iterations + model.solve_rate().iterations;
    stats.solves += 2;
    stats.solve_seconds += timer.seconds();
    timer.reset();
    cache.refresh_all();
    stats.stress_seconds += timer.seconds();
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
    stats.solve_seconds += timer.seconds();
    if (model.stiffness_changed()) {
        relax_all(model, cache, stats); // new B matrices: every stress changes
        return;
    }
    timer.reset();
    cache.advance(t - t0);
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

/// Re-solves the equilibrium after a change at `seeds` (vertices, sorted and unique): locally
/// (§5.8) or globally as the options say, with the accounting every FEM loop keeps; the seeds
/// join `rate_seeds` (settled at the next time step); then the §5.8.3 check unless `check` is
/// false (a trial that may still be undone). `released` gets the strain energy the solve
/// released. Returns the vertices that moved.
inline const std::vector<std::size_t>& relax_after_change(sim::FemModel& model, const std::vector<std::size_t>& seeds,
                                                          double& radius, const sim::LocalRelaxOptions& local,
                                                          const FractureOptions& options, RunStats& stats,
                                                          std::vector<std::size_t>& rate_seeds, bool check = true,
                                                          double* released = nullptr) {
    Timer timer;
    const sim::SolveStats s = options.local_relaxation ? model.relax_local(seeds, radius, local) : model.relax();
    if (released) *released = s.energy_release;
    stats.solver_iterations += s.iterations;
    ++stats.solves;
    if (options.local_relaxation) {
        ++stats.local_solves;
        stats.local_nodes += s.nodes;
        stats.local_fallbacks += s.fell_back;
    }
    rate_seeds.insert(rate_seeds.end(), seeds.begin(), seeds.end());
    stats.solve_seconds += timer.seconds();
    if (check) check_drift(model, options, radius, stats);
    return model.last_updated_vertices();
}

/// A time step's clean-up done where the residual is (§5.8.3): up to three local solves seeded
/// at the nodes whose residual force exceeds FractureOptions::cleanup_tolerance of a
/// threshold-level force, each pushing out no more than that; the stresses are refreshed where
/// nodes moved. Returns false when that did not bring every nodal force under the target (the
/// caller relaxes globally). `radius` starts the local sets and is kept.
inline bool settle_locally(sim::FemModel& model, StressCache& cache, const FractureOptions& options,
                           const sim::LocalRelaxOptions& local, double& radius, RunStats& stats) {
    const double target = options.cleanup_tolerance * model.force_scale();
    for (int round = 0;; ++round) {
        Timer timer;
        const std::vector<std::size_t> seeds = model.vertices_over_residual(target);
        if (seeds.empty() || round == 3) {
            stats.solve_seconds += timer.seconds();
            return seeds.empty();
        }
        sim::LocalRelaxOptions to_target = local;
        to_target.tolerance = target / model.max_residual_force();
        const sim::SolveStats s = model.relax_local(seeds, radius, to_target);
        stats.solver_iterations += s.iterations;
        ++stats.solves;
        ++stats.local_solves;
        stats.local_nodes += s.nodes;
        stats.local_fallbacks += s.fell_back;
        stats.solve_seconds += timer.seconds();
        timer.reset();
        if (s.fell_back)
            cache.refresh_all(); // solved globally: every node moved
        else
            cache.refresh_around(model.last_updated_vertices());
        stats.stress_seconds += timer.seconds();
    }
}

/// Once per time step (§5.8): settles the rate solution around `rate_seeds` (the vertices whose
/// elements changed since the last step; cleared), then relaxes globally when the local
/// relaxations have left forces that could shift a stress by 1e-3 of a threshold (the thesis
/// relaxes globally every time step): locally where that settles it, else globally. Refreshes
/// the cache where needed; times go to `stats`.
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
        stats.solve_seconds += timer.seconds();
        // Where the residual is first: a global clean-up is a solve over the whole layer and
        // a refresh of every stress, O(N) per time step (the time steps grow like the area).
        double radius = rate_radius;
        if (options.cleanup_tolerance > 0 && settle_locally(model, cache, options, local, radius, stats)) {
            stats.local_cleanups += 1;
        } else {
            stats.global_cleanups += 1;
            relax_all(model, cache, stats);
        }
    } else {
        stats.solve_seconds += timer.seconds();
    }
    if (options.hooks.before_time_step) options.hooks.before_time_step(model);
}

} // namespace crackle::fracture
