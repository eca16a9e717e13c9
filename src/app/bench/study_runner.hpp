#pragma once
/// @file Running one study run: a child `crackle simulate` process with a time limit (its own
/// wall time and peak memory; a crash or hang ends only that run), or the in-process 1D bar.

#include "app/bench/study_metrics.hpp"
#include "app/bench/study_plan.hpp"
#include "core/json.hpp"

#include <filesystem>
#include <functional>
#include <string>

namespace crackle::app {

struct RunOutcome {
    std::string status = "ok"; ///< ok, "exit N", "signal N", timeout
    double wall = 0;           ///< seconds around the child (the report's own total is in `report`)
    double peak_memory_mb = 0; ///< the child's maximum resident set
    Json report;               ///< the child's --json report (an object when status is ok)
    std::string events_csv;    ///< the child's --events output
    std::string message;       ///< the first line the child printed on stderr
};

/// Runs `binary -q simulate <preset> --set …` in `work_dir`, killing it after `time_limit`
/// seconds; `tick(elapsed)` is called about 20 times a second while it runs.
RunOutcome run_child(const std::filesystem::path& binary, const StudyRun& run, const std::filesystem::path& work_dir,
                     double time_limit, const std::function<void(double)>& tick);

/// The statistics and timings of a finished run, read from its report (and arrest_height from
/// its events): the columns of the study's runs.csv.
StatMap read_stats(const RunOutcome& outcome);

/// The 1D bar of App. A with `run.elements` sub-segments: the report holds first_event_time,
/// closed_form_time and tension_error (max |T − T_exact| / max T_exact at 0.9 t*).
RunOutcome run_bar(const StudyRun& run);

/// A python3 that imports matplotlib: $CRACKLE_PYTHON, python3 on the PATH, /usr/bin/python3;
/// "" when none does.
std::string find_python_with_matplotlib();

/// Runs the embedded chart script scripts/<name>.py as `python -c <script> args…`, stdout to
/// `log` and stderr to `log`.err. Throws NumericError, naming the log, when it fails.
void run_chart_script(const std::string& python, const std::string& name, const std::vector<std::string>& args,
                      const std::filesystem::path& log);

} // namespace crackle::app
