#pragma once
/// @file `crackle bench scale`: how a simulation's cost grows (docs/benchmarks.md, "Scale"). Two
/// series of mud runs, each a child process timed with its peak memory:
/// - the scale series: tiles of growing area at a fixed resolution per layer thickness (2
///   elements per h², the "auto" rule), so the cost should grow like the area;
/// - the refinement series: the preset's own tile at growing resolution, the speed-vs-accuracy
///   study's error-vs-time curve (errors against the study's reference, in its seed spreads).
/// With --baseline the same runs of another executable, interleaved, so one chart shows both.

#include <filesystem>
#include <ostream>
#include <vector>

namespace crackle::app {

struct ScaleArgs {
    std::filesystem::path baseline; ///< another crackle executable to compare with ("" = none)
    int seeds = 1;                  ///< seeds per point
    bool quick = false;             ///< small sizes: a smoke run (what the tests run)
    bool charts = true;             ///< draw scale.png with python3 + matplotlib
    std::filesystem::path out_dir;  ///< scale.csv, scale.json, scale.png ("" = bench)
};

/// The side (m) of a square mud tile that holds `elements` at the "auto" rule's 2 elements per
/// h² of the preset's mean layer thickness: the tile that grows with the count.
double mud_auto_side(long long elements);

/// Log-log least-squares slope of cost against size (NaN with fewer than two points).
double loglog_slope(const std::vector<double>& size, const std::vector<double>& cost);

/// Runs both series and prints Markdown tables with the fitted slopes. Exit 0; 2 when the
/// baseline cannot be run.
int scale_command(const ScaleArgs& args, std::ostream& out);

} // namespace crackle::app
