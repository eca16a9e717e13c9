#pragma once
/// @file What every fracture loop shares: the common [simulation] options of the loop, the
/// observers tests hook into, and the common counters of a run (per-method counters live with
/// each method).

#include "fracture/crack_pattern.hpp"

#include <functional>
#include <vector>

namespace crackle::sim {
class FemModel;
}

namespace crackle::fracture {

/// Observers of a run (tests measure against global solves with them). They are not settings:
/// any two compare equal.
struct RunHooks {
    /// Called after every event with the model as the event left it (FEM methods).
    std::function<void(const sim::FemModel&, const Event&)> after_event;
    /// Called at every time step once the equilibrium and its rate are settled, before Alg. 5
    /// looks for the next fracture time with them (FEM methods).
    std::function<void(const sim::FemModel&)> before_time_step;
    bool operator==(const RunHooks&) const { return true; }
};

/// Parameters of the fracture loop ([simulation] preset keys every method reads).
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
    /// A time step's clean-up (when some nodal force passes 1e-3 of a threshold-level one) first
    /// solves locally around the nodes over this share and accepts the result when no nodal force
    /// is left over it; otherwise, or with 0, it relaxes globally.
    double cleanup_tolerance = 1e-4;
    RunHooks hooks;

    bool operator==(const FractureOptions&) const = default;
};

/// What a run did and where the time went, for every method.
struct RunStats {
    std::size_t time_steps = 0, solves = 0;
    /// Whole-stiffness rebuilds because shrinkage changed the reference shapes (FemOptions::
    /// stiffness_refresh).
    std::size_t stiffness_rebuilds = 0;
    long long solver_iterations = 0;
    std::size_t local_solves = 0, local_nodes = 0, local_fallbacks = 0, global_cleanups = 0;
    /// Time-step clean-ups settled without a global relaxation (a local set that grew past
    /// LocalRelaxOptions::max_fraction was solved globally instead: local_fallbacks counts it).
    std::size_t local_cleanups = 0;
    std::size_t drift_relaxations = 0; ///< global relaxations after the §5.8.3 residual check
    double solve_seconds = 0;          ///< equilibrium: local and global solves, moving along the rate
    double stress_seconds = 0;         ///< stress evaluation, candidate search, Alg. 5's bracketing
    double topology_seconds = 0;       ///< removing and subdividing elements, matrix updates
    double total_seconds = 0;
    double setup_seconds = 0; ///< the first global solve and stress evaluation (in total_seconds)
};

/// The event log of a run and its cap (simulation.max_events): `full(t)` says when the run must
/// stop (and warns, naming the time reached); `add()` records an event and tells the observer.
class EventLog {
public:
    explicit EventLog(const FractureOptions& options) : m_options(options) {}
    bool full(double time);
    template <class Model> void add(const Event& ev, const Model& model) {
        m_events.push_back(ev);
        if (m_options.hooks.after_event) m_options.hooks.after_event(model, ev);
    }
    void add(const Event& ev) { m_events.push_back(ev); }
    bool capped() const { return m_capped; }
    std::size_t size() const { return m_events.size(); }
    std::vector<Event> take() { return std::move(m_events); }

private:
    const FractureOptions& m_options;
    std::vector<Event> m_events;
    bool m_capped = false;
};

} // namespace crackle::fracture
