#include "app/commands/bake.hpp"

#include "app/run/bake_run.hpp"
#include "app/run/batch.hpp"
#include "app/run/report.hpp"
#include "core/error.hpp"

namespace crackle::app {

namespace {

/// The preset request with the bake's flags (--size, --maps, --bit-depth, --preview) as the typed
/// values of their keys.
io::PresetRequest bake_request(const BakeArgs& args, bool with_size) {
    return with_bake_flags(args.preset, {with_size ? args.size : "", args.maps, args.bit_depth, args.preview});
}

BakeOutputs bake_outputs(const BakeArgs& args) {
    BakeOutputs o;
    o.dir = args.out_dir.empty() ? std::filesystem::path("out") : std::filesystem::path(args.out_dir);
    o.name_pattern = args.name;
    o.meshes = args.meshes;
    o.split_pieces = args.split_pieces;
    o.json_path = args.json_path;
    return o;
}

/// `bake --seeds` / `--shard`: a batch of one preset over a seed list.
int bake_seeds(const BakeArgs& args, const GlobalOptions& global, std::ostream& out) {
    if (args.preview || args.watch || !args.json_path.empty())
        throw InputError("--seeds", "a seed list writes one report per seed beside its maps",
                         "leave out --preview, --watch and --json with --seeds");
    std::vector<Variant> variants;
    const io::PresetRequest base = bake_request(args, false); // the batch adds --size
    for (const std::uint64_t seed : parse_seed_list(args.seeds.empty() ? "" : args.seeds, "--seeds " + args.seeds)) {
        Variant v;
        v.index = variants.size();
        v.preset = base;
        v.preset.seed = static_cast<std::int64_t>(seed);
        v.name = args.name;
        v.where = "--seeds (seed " + std::to_string(seed) + ")";
        variants.push_back(std::move(v));
    }
    BatchOptions options;
    options.out_dir = bake_outputs(args).dir;
    options.size = args.size;
    options.outputs = bake_outputs(args);
    options.outputs.json_path.clear();
    options.shader_dir = args.shader_dir;
    options.pattern = {args.pattern_path, !args.no_cache};
    options.shard = resolve_shard(args.shard);
    return run_batch(variants, options, global, out);
}

} // namespace

int bake_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out) {
    if (!args.seeds.empty() || !args.shard.empty()) {
        if (args.seeds.empty())
            throw InputError("--shard " + args.shard, "a shard of nothing",
                             "give --seeds 1-100 (or use crackle batch)");
        return bake_seeds(args, global, out);
    }
    StepTimes times;
    // --preview swaps in the reduced model once the preset's own values are known.
    const RunPlan plan =
        make_run_plan(io::load_preset(bake_request(args, true)), {.bake = true, .preview = args.preview});
    const BakeOutputs outputs = bake_outputs(args);
    const OutputNames names = bake_names(plan, outputs, "", !args.name.empty());
    Baked b;
    const Json report = bake_one(plan, outputs, names, args.shader_dir, {args.pattern_path, !args.no_cache}, times, &b);

    if (!global.quiet) {
        out << "crackle bake: " << plan.record.preset << " (" << mesh::to_string(b.sim.scene->surface.kind()) << ", "
            << b.sim.pattern.method << "), seed " << b.sim.scene->seed << ", " << b.maps.width << "×"
            << b.maps.height_px << " px\n";
        print_simulation(out, b.sim);
        out << "  maps         " << report.find("files")->elements().size() << " files in " << outputs.dir.string()
            << "/ (" << names.base() << " ...); displacement 1.0 = " << fmt("%.4g", b.maps.height_scale * 1000)
            << " mm\n";
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
