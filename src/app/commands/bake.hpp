#pragma once
/// @file `crackle bake`: the whole pipeline to a texture set (and its seed lists, a batch of one preset).

#include "app/commands/global_options.hpp"
#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct BakeArgs {
    io::PresetRequest preset;
    std::string size;       ///< --size N or WxH ("" = bake.size)
    bool preview = false;   ///< --preview: 512 px, 2 samples
    bool watch = false;     ///< --watch: re-bake the preview whenever the preset file changes
    std::string shader_dir; ///< read GLSL from here instead of the embedded copies
    std::string out_dir;    ///< "" = out/
    std::string json_path;
    std::string pattern_path;        ///< --pattern: bake this crack pattern file, no simulation
    bool no_cache = false;           ///< --no-cache: neither read nor fill the pattern cache
    std::string maps;                ///< --maps (bake.maps)
    std::string bit_depth;           ///< --bit-depth (bake.bit_depth)
    std::string name;                ///< --name: the output name pattern (bake.name)
    std::vector<std::string> meshes; ///< --mesh glb,gltf,obj: meshes beside the maps
    bool split_pieces = false;       ///< --pieces: one mesh node per piece
    std::string seeds;               ///< --seeds 1-100,200: one bake per seed (a batch)
    std::string shard;               ///< --shard i/N: this slice of the seeds
};

/// `crackle bake`: the whole pipeline to a texture set.
int bake_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out);

} // namespace crackle::app
