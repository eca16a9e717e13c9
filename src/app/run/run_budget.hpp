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

/// The plan's cost (make_run_plan stores it as RunPlan::estimate): the method's memory per
/// element, the maps' pixels when the run bakes, and the progress plan's stage weights.
RunEstimate estimate_run(const RunPlan& plan);

/// Checks a run against the budget before any work and then watches it: refuses (InputError,
/// exit 2) a run whose estimated memory passes the memory budget; warns when the estimate is
/// over 10 minutes, over half the memory budget, or over --max-time.
class RunBudget {
public:
    /// @param what  for messages: "simulation of mud", "bake of mud (seed 3)"
    RunBudget(const RunPlan& plan, const std::string& what);

    const RunEstimate& estimate() const { return m_estimate; }

private:
    RunEstimate m_estimate;
    std::optional<BudgetScope> m_scope;
};

} // namespace crackle::app
