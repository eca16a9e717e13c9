#pragma once
/// @file `crackle batch`: a manifest's variants in this shard, its list, or the merge (docs/farm.md).

#include "app/commands/global_options.hpp"
#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct BatchArgs {
    std::string manifest;               ///< JSON Lines or TOML (docs/farm.md)
    std::string out_dir;                ///< "" = out/
    std::vector<std::string> overrides; ///< --set, before each variant's own
    std::string size, maps, bit_depth;  ///< as in bake
    std::vector<std::string> meshes;
    bool split_pieces = false;
    std::string shard; ///< --shard i/N or N ("" = from Slurm / Kubernetes, else 1/1)
    bool merge = false;
    bool list = false; ///< --list: print the shard's variants, bake nothing
    std::string shader_dir;
    bool no_cache = false;
};

/// `crackle batch`: the manifest's variants in this shard, or --merge of the shards' summaries.
int batch_command(const BatchArgs& args, const GlobalOptions& global, std::ostream& out);

} // namespace crackle::app
