#pragma once
/// @file `crackle simulate`: grow and crack the preset's surface, report the pattern.

#include "app/commands/global_options.hpp"
#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct SimulateArgs {
    io::PresetRequest preset;
    std::string json_path;   ///< report (design.md field names)
    std::string events_path; ///< CSV of fracture events
    std::string png_path;    ///< quick preview of the crack pattern in texture space
    int png_size = 512;
    std::string save_path; ///< --save: the crack pattern file (bake/export --pattern read it)
    bool no_cache = false; ///< --no-cache: do not store the pattern in the cache
};

/// `crackle simulate`: grow and crack the preset's surface, report the pattern statistics.
int simulate_command(const SimulateArgs& args, const GlobalOptions& global, std::ostream& out);

} // namespace crackle::app
