#pragma once
/// @file Where a run's crack pattern comes from: a fresh simulation, a pattern file given with
/// `--pattern`, or the pattern cache (docs/farm.md "Pattern files and the cache").
///
/// The cache keys a pattern by everything that decides it: every preset value outside [post]
/// and [bake] (with `simulation.elements = "auto"` resolved, since it follows bake.size, and
/// the bytes of any image a variation reads), the seed, and the build of crackle that made it.
/// A change to a colour, a relief key or the map size therefore reuses the pattern; a change
/// to a simulation key, the seed or the program simulates again. Files are written atomically
/// (temporary file, then rename) and checked whole when read, so concurrent runs sharing a
/// cache folder at worst simulate the same pattern twice and never read a half-written one.

#include "app/run/pipeline.hpp"
#include "fracture/pattern_file.hpp"

#include <filesystem>
#include <string>

namespace crackle::app {

struct PatternOptions {
    std::string load_path; ///< --pattern FILE: use this pattern, never simulate
    bool use_cache = true; ///< --no-cache turns the cache off for one run
};

/// The cache folder: $CRACKLE_CACHE, else $XDG_CACHE_HOME/crackle, else ~/.cache/crackle.
/// Empty when the cache is off (CRACKLE_CACHE=off or 0, or no home folder).
std::filesystem::path cache_dir();

/// The text the cache keys on (one "key = value" line per simulation-relevant value; `plan`'s
/// element count for "auto"): make_run_plan stores it as RunPlan::simulation_key.
std::string simulation_key(const io::Preset& preset, const RunPlan& plan);

/// This build of crackle (a hash of the running executable): patterns from any other build are
/// never served from the cache.
const std::string& build_id();

/// The pattern file of a finished simulation: the pattern, the preset and seed that made it,
/// the simulation key and the run's counters.
std::vector<std::uint8_t> pattern_file_bytes(const SimulationResult& result);

/// Stores a finished simulation in the cache (best effort: a cache that cannot be written is
/// a warning, never a failed run).
void cache_store(const SimulationResult& result);

/// The simulation a bake or export works from: the pattern file when given, else the cache's
/// pattern for this preset when there is one, else a fresh simulation (stored in the cache).
/// result.pattern_source says which.
SimulationResult obtain_simulation(const RunPlan& plan, const PatternOptions& options, StepTimes& times);

} // namespace crackle::app
