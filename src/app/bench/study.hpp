#pragma once
/// @file `crackle bench` (no micro-benchmark named): the speed-vs-accuracy study. Every fracture
/// method at several resolutions and seeds on scenes with known answers; each run is a child
/// `crackle simulate` process (its own wall time and peak memory, a time limit, a crash cannot
/// end the study). Writes runs.csv (a row per run), points.csv (a row per method × resolution,
/// seed-averaged), each with per-statistic errors in the reference's seed spreads and tolerance
/// verdicts, summary.md and the charts (scripts/bench_charts.py, matplotlib). docs/benchmarks.md
/// defines the scenes and error metrics.

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct StudyArgs {
    bool quick = false;               ///< a subset in about a minute (what CI runs)
    std::filesystem::path out_dir;    ///< where the CSVs and charts go
    std::vector<std::string> methods; ///< empty = all of study_methods()
    std::vector<std::string> scenes;  ///< empty = all of study_scenes()
    int seeds = 0;                    ///< per point: 0 = 3 (1 with --quick); of a made reference: 0 = 8
    bool make_reference = false;      ///< run the reference runs and write reference.json instead
    bool charts = true;               ///< draw the charts (needs python3 with matplotlib)
    double time_limit = 0;            ///< seconds per run; 0 = 600 (60 with --quick)
    std::filesystem::path binary;     ///< the crackle executable to run; empty = this process's
    std::filesystem::path reference;  ///< reference.json to read; empty = the embedded one
};

/// Runs the study (or the reference runs) and prints a summary table. Exit code 0, or 2 on bad
/// arguments (checked before anything runs).
int study_command(const StudyArgs& args, std::ostream& out);

/// Method variants of the study, from the registry (each method's MethodInfo::study): fem-split,
/// fem-split-tip, fem-remove, mass-spring-regular, mass-spring-random, graph-fem.
std::vector<std::string> study_methods();

/// Scenes: bar, film, film-cylinder, film-sphere, arrest, mud, bark.
const std::vector<std::string>& study_scenes();

} // namespace crackle::app
