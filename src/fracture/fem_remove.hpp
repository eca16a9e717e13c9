#pragma once
/// @file Fracture by element removal (Federl 2002, §5.6): remove the element with the highest
/// stress/threshold ratio, re-relax, repeat; when none is over threshold, jump to the time of
/// the next fracture (Alg. 5); subdivide coarse elements instead of removing them (Alg. 8).

#include "core/rng.hpp"
#include "core/timer.hpp"
#include "fracture/crack_pattern.hpp"
#include "sim/fem_model.hpp"

#include <functional>

namespace crackle::fracture {

/// Parameters of the fracture loop ([simulation] preset keys).
struct FractureOptions {
    double duration = 1.0;         ///< simulated time
    double min_element_size = 0.0; ///< subdivide candidates longer than this (m); 0 = never
    std::size_t max_events = 1000000;
    double time_tolerance = 1e-9; ///< bisection stops at this fraction of the duration
    /// Re-solve only around each change (§5.8), with a global relaxation at every time step;
    /// false re-solves globally after every event.
    bool local_relaxation = true;
    /// Local relaxation stops growing its set when the force pushed out of it is below this
    /// share of the change's largest nodal force (sim::LocalRelaxOptions::tolerance).
    double local_tolerance = 1e-2;
    /// §5.8.3: after every local relaxation the global residual is checked, and when its
    /// largest nodal force passes this share of a threshold-level one (FemModel::force_scale)
    /// the model is relaxed globally, so a cascade of local relaxations cannot drift: the
    /// stress error stays below a few times this share of the threshold whatever the cascade's
    /// length. The rate solution is checked the same way (per unit of the run's duration) at
    /// every time step, before Alg. 5 uses it.
    double drift_tolerance = 1e-2;
    /// Called after every event with the model as the event left it (tests measure the drift
    /// of local relaxation against a global solve with it). Empty: nothing is called.
    std::function<void(const sim::FemModel&, const Event&)> after_event;
    /// Called at every time step once the equilibrium and its rate are settled, before Alg. 5
    /// looks for the next fracture time with them.
    std::function<void(const sim::FemModel&)> before_time_step;
};

/// What the run did and where the time went.
struct RunStats {
    std::size_t removals = 0, subdivisions = 0, time_steps = 0, solves = 0;
    /// Whole-stiffness rebuilds because shrinkage changed the reference shapes (FemOptions::
    /// stiffness_refresh).
    std::size_t stiffness_rebuilds = 0;
    /// fem-split: new fractures, accepted and rejected (Griffith) tip extensions, cuts moved
    /// onto a vertex by edge collapse, cuts snapped to a vertex that could not move.
    std::size_t splits = 0, extensions = 0, arrests = 0, collapses = 0, snaps = 0;
    std::size_t smoothed = 0;       ///< fem-split: node moves by angle-based smoothing (§5.7.9)
    std::size_t vm_refinements = 0; ///< fem-split: bisections by the von Mises indicator (§5.7.7)
    std::size_t submodels = 0;      ///< fem-split: temporary tip sub-models (§5.7.8)
    std::size_t flips = 0;          ///< fem-split: edge flips of slivers near cuts (§5.7.5)
    long long solver_iterations = 0;
    std::size_t local_solves = 0, local_nodes = 0, local_fallbacks = 0, global_cleanups = 0;
    std::size_t drift_relaxations = 0; ///< global relaxations after the §5.8.3 residual check
    double solve_seconds = 0;          ///< equilibrium: local and global solves, moving along the rate
    double stress_seconds = 0;         ///< stress evaluation, candidate search, Alg. 5's bracketing
    double topology_seconds = 0;       ///< removing and subdividing elements, matrix updates
    double total_seconds = 0;
    double setup_seconds = 0; ///< fem-split: the first global solve and stress evaluation (in total_seconds)
    /// fem-split: where and when each crack tip stopped (Griffith, Alg. 11), kind "arrest",
    /// position the tip's reference point, ratio its stress over threshold then.
    std::vector<Event> arrests_at;
};

/// Runs the element-removal model from the model's current time to `options.duration`.
/// Ties between equally stressed candidates are broken with `rng`.
CrackPattern run_fem_remove(sim::FemModel& model, const FractureOptions& options, Rng& rng, RunStats* stats = nullptr);

/// Builds the crack pattern of a model's current state (shared by the FEM methods).
CrackPattern pattern_from_model(const sim::FemModel& model, const std::string& method, std::size_t elements_initial);

} // namespace crackle::fracture
