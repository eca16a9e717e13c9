#include "app/run/run_budget.hpp"

#include "app/run/pipeline.hpp"
#include "core/log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace crackle::app {

namespace {

constexpr double kMiB = 1024.0 * 1024.0;

} // namespace

RunEstimate estimate_run(const RunPlan& plan) {
    RunEstimate e;
    for (const ProgressStage& stage : progress_stages(plan))
        e.seconds += stage.weight;
    const double elements = static_cast<double>(plan.elements.elements);
    // Peak bytes per initial element: the method's own figure (its method.cpp says how it was measured).
    const double simulation = elements * plan.bytes_per_element;
    double maps = 0;
    if (plan.bakes) {
        // 2235 MB for a 4096² mud bake and 309 MB at 1024² (`/usr/bin/time -f %M crackle -q bake
        // mud --size N`): about 123 bytes a pixel for the maps, their 16-bit copies, the GL targets
        // and the encoder.
        maps = 140.0 * plan.map.pixels();
    }
    // The process itself: 64 MiB (`crackle simulate` of 2000 elements peaks at 73 MiB), and 48 MiB
    // more for a bake's GL driver (a 64² bake of a few hundred elements peaks at 105–126 MiB;
    // scripts/soak over 500 random presets, docs/reliability.md).
    e.bytes = (plan.bakes ? 112 : 64) * kMiB + simulation + maps;
    e.memory_key = maps > simulation ? "bake.size" : "simulation.elements";
    return e;
}

RunBudget::RunBudget(const RunPlan& plan, const std::string& what) : m_estimate(plan.estimate) {
    const BudgetLimits& limits = budget_limits();
    const double budget = static_cast<double>(memory_budget_bytes());
    const std::string need = format_bytes(m_estimate.bytes);
    const std::string where = plan.record.where(m_estimate.memory_key);
    if (m_estimate.bytes > budget) {
        const std::string of =
            limits.memory_source.empty() ? " (90 % of this machine's memory)" : ", set by " + limits.memory_source;
        throw InputError(
            where,
            what + " would need about " + need + " of memory, more than its budget of " + format_bytes(budget) + of,
            "lower " + m_estimate.memory_key
                + (limits.memory_source.empty() ? "" : ", or raise " + limits.memory_source) + "; nothing was started");
    }
    const std::string time = format_seconds(m_estimate.seconds);
    if (limits.seconds > 0 && m_estimate.seconds > 3 * limits.seconds)
        log::warn(what, " may take about ", time, ", more than ", limits.time_source, " ",
                  format_seconds(limits.seconds),
                  " allows; it will stop there with nothing written (a rough "
                  "estimate)");
    else if (m_estimate.seconds > 600 || m_estimate.bytes > 0.5 * budget)
        log::warn(what, " may take about ", time, " and ", need,
                  " of memory (a rough estimate; --max-time "
                  "and --max-memory bound a run)");
    char line[160];
    std::snprintf(line, sizeof line, "estimate: %.3g s, %.0f MiB (%s)", m_estimate.seconds, m_estimate.bytes / kMiB,
                  m_estimate.memory_key.c_str());
    log::info(line); // scripts/soak compares these with what the run took
    m_scope.emplace(what);
}

} // namespace crackle::app
