#pragma once
/// @file What a run will cost, said before it starts (issue 16, "bounded work"): an estimate of
/// its wall time and peak memory from the preset, a refusal (exit 2) when the memory will not
/// fit the budget, a warning when the run is long or outgrows --max-time, and the BudgetScope
/// that holds the run to its budget (core/budget.hpp).

#include "app/run/run_plan.hpp"
#include "core/budget.hpp"
#include "io/preset.hpp"

#include <optional>
#include <string>

namespace crackle::app {

/// Rough cost of one run on two cores.
struct RunEstimate {
    double seconds = 0;     ///< the progress plan's stage weights, summed (within a few × of the truth)
    double bytes = 0;       ///< peak resident memory (within about 1.5×; docs/reliability.md)
    std::string memory_key; ///< the key that dominates the memory: "bake.size" or "simulation.elements"
};

RunEstimate estimate_run(const io::Preset& preset, const RunPlan& plan, bool bake);

/// Checks a run against the budget before any work and then watches it: refuses (InputError,
/// exit 2) a run whose estimated memory passes the memory budget; warns when the estimate is
/// over 10 minutes, over half the memory budget, or over --max-time.
class RunBudget {
public:
    /// @param what  for messages: "simulation of mud", "bake of mud (seed 3)"
    RunBudget(const io::Preset& preset, const RunPlan& plan, bool bake, const std::string& what);

    const RunEstimate& estimate() const { return m_estimate; }

private:
    RunEstimate m_estimate;
    std::optional<BudgetScope> m_scope;
};

} // namespace crackle::app
