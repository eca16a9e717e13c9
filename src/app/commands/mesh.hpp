#pragma once
/// @file `crackle mesh`: the preset's surface discretized, its figures reported.

#include "app/commands/global_options.hpp"
#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct MeshArgs {
    io::PresetRequest preset;
    std::string obj_path;  ///< "" = no OBJ
    std::string json_path; ///< "" = no report file
};

/// `crackle mesh`: discretize the preset's surface and report mesh figures.
int mesh_command(const MeshArgs& args, const GlobalOptions& global, std::ostream& out);

} // namespace crackle::app
