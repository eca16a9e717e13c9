#pragma once
/// @file `crackle export`: the piece mesh as OBJ or glTF with its maps.

#include "app/commands/global_options.hpp"
#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct ExportArgs {
    io::PresetRequest preset;
    std::string format = "glb"; ///< obj | gltf | glb
    std::string out_path;       ///< "" = out/<name>.<format>
    std::string size;           ///< --size N or WxH ("" = bake.size)
    std::string json_path;
    std::string shader_dir;
    std::string pattern_path;
    bool no_cache = false;
    bool split_pieces = false; ///< --pieces: one node / object per piece
};

/// `crackle export`: the piece mesh as OBJ or glTF with its PBR maps.
int export_command(const ExportArgs& args, const GlobalOptions& global, std::ostream& out);

} // namespace crackle::app
