#include "app/commands/batch.hpp"

#include "app/run/batch.hpp"

namespace crackle::app {

int batch_command(const BatchArgs& args, const GlobalOptions& global, std::ostream& out) {
    const std::vector<Variant> variants = read_manifest(args.manifest);
    BatchOptions options;
    options.out_dir = args.out_dir.empty() ? std::filesystem::path("out") : std::filesystem::path(args.out_dir);
    options.overrides = args.overrides;
    options.maps = args.maps;
    options.bit_depth = args.bit_depth;
    options.size = args.size;
    options.outputs.meshes = args.meshes;
    options.outputs.split_pieces = args.split_pieces;
    options.shader_dir = args.shader_dir;
    options.pattern = {"", !args.no_cache};
    options.manifest = args.manifest;
    if (args.merge) return merge_batch(variants, options, out);
    options.shard = resolve_shard(args.shard);
    if (args.list) return list_batch(variants, options, out);
    return run_batch(variants, options, global, out);
}

} // namespace crackle::app
