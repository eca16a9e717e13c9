#pragma once
/// @file `crackle bench speedup --baseline OLD`: this build against another crackle executable on
/// the shipped presets, side by side in one run (interleaved, seed by seed), timed and scored with
/// the study's error metrics (docs/benchmarks.md, "Speed-ups and what they kept").

#include <filesystem>
#include <ostream>

namespace crackle::app {

struct SpeedupArgs {
    std::filesystem::path baseline; ///< the other crackle executable (the starting point)
    int seeds = 3;                  ///< seeds per preset
    bool quick = false;             ///< one seed, small models: a smoke run
    std::filesystem::path out_dir;  ///< where speedup.json goes ("" = nowhere)
};

/// Runs mud and bark with both executables (and the baseline at the 8000 elements) and
/// prints a Markdown table: median wall time, speed ratio, peak memory, the pattern statistics'
/// seed means and spreads, their largest shift in units of the starting point's spread, and the
/// errors against the study's reference (rms z in its seed spreads, the worst statistic, and
/// whether all are within the texture user's tolerance). Exit 0, or 2 when the baseline cannot be run.
int speedup_command(const SpeedupArgs& args, std::ostream& out);

} // namespace crackle::app
