#include "app/bake_run.hpp"
#include "app/batch.hpp"
#include "app/commands.hpp"
#include "app/report.hpp"
#include "app/run_budget.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "io/mesh_files.hpp"
#include "io/resolution.hpp"

namespace crackle::app {

namespace {

/// --maps and --bit-depth are shorthands for the preset keys.
io::PresetRequest bake_request(const BakeArgs& args) {
    io::PresetRequest request = args.preset;
    if (!args.maps.empty()) request.overrides.push_back("bake.maps=\"" + args.maps + "\"");
    if (!args.bit_depth.empty()) request.overrides.push_back("bake.bit_depth=\"" + args.bit_depth + "\"");
    return request;
}

/// The bake's preset; --preview swaps in the reduced model (io::element_count's preview rule,
/// no tip sub-model) after the preset's own values are known.
io::Preset load_bake_preset(const BakeArgs& args) {
    io::PresetRequest request = with_bake_overrides(bake_request(args), args.size, args.preview);
    if (!args.preview) return io::load_preset(request);
    const io::Preset full = io::load_preset(request);
    const io::ElementCount reduced = io::element_count(full, true);
    request.overrides.push_back("simulation.elements=" + std::to_string(reduced.elements));
    if (full.text("simulation.method") == "fem-split") request.overrides.push_back("simulation.tip_submodel=0");
    if (reduced.automatic) log::info(reduced.reason);
    return io::load_preset(request);
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
    const io::PresetRequest base = bake_request(args);
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
    const io::Preset preset = load_bake_preset(args);
    const BakeOutputs outputs = bake_outputs(args);
    const OutputNames names = bake_names(preset, outputs, "", !args.name.empty());
    Baked b;
    const Json report =
        bake_one(preset, outputs, names, args.shader_dir, {args.pattern_path, !args.no_cache}, times, &b);

    if (!global.quiet) {
        out << "crackle bake: " << preset.name << " (" << mesh::to_string(b.sim.scene->surface.kind()) << ", "
            << b.sim.pattern.method << "), seed " << b.sim.scene->seed << ", " << b.maps.width << "×"
            << b.maps.height_px << " px\n";
        print_simulation(out, preset, b.sim);
        out << "  maps         " << report.find("files")->elements().size() << " files in " << outputs.dir.string()
            << "/ (" << names.base() << " ...); displacement 1.0 = " << fmt("%.4g", b.maps.height_scale * 1000)
            << " mm\n";
        print_times(out, times);
    }
    return 0;
}

int batch_command(const BatchArgs& args, const GlobalOptions& global, std::ostream& out) {
    const std::vector<Variant> variants = read_manifest(args.manifest);
    BatchOptions options;
    options.out_dir = args.out_dir.empty() ? std::filesystem::path("out") : std::filesystem::path(args.out_dir);
    options.overrides = args.overrides;
    if (!args.maps.empty()) options.overrides.push_back("bake.maps=\"" + args.maps + "\"");
    if (!args.bit_depth.empty()) options.overrides.push_back("bake.bit_depth=\"" + args.bit_depth + "\"");
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

int export_command(const ExportArgs& args, const GlobalOptions& global, std::ostream& out) {
    Timer total;
    StepTimes times;
    const io::Preset preset = io::load_preset(with_bake_overrides(args.preset, args.size, false));
    const std::string name = bake_names(preset, BakeOutputs{}).base();
    const std::filesystem::path file = args.out_path.empty() ? std::filesystem::path("out") / (name + "." + args.format)
                                                             : std::filesystem::path(args.out_path);
    check_output_path(file, "--out");
    if (!args.json_path.empty()) check_output_path(args.json_path, "--json");
    const RunPlan plan = make_run_plan(preset);
    const RunBudget budget(preset, plan, true, "the export of " + preset.name);
    const ProgressPlan progress(progress_stages(plan, true));
    const Baked b = bake_pipeline(preset, plan, times, args.shader_dir, {args.pattern_path, !args.no_cache});

    progress_stage("encode");
    Timer step;
    const std::vector<io::OutputFile> files =
        io::mesh_files(b.pieces, b.maps, {}, file, io::MeshFileOptions{args.format, args.split_pieces});
    times.emplace_back("export", step.seconds());
    progress_stage("write");
    AtomicOutput output;
    Json written = Json::array();
    for (const io::OutputFile& f : files) {
        output.write(f.path, f.bytes);
        written.push_back(f.path.string());
    }
    times.emplace_back("total", total.seconds());
    Json report = simulation_report(preset, b.sim, times);
    report["command"] = "export";
    report["format"] = args.format;
    report["split_pieces"] = args.split_pieces;
    report["displacement_scale_m"] = b.maps.height_scale;
    report["vertices"] = b.pieces.vertices.size();
    report["triangles"] = b.pieces.triangles.size();
    report["pieces"] = b.pieces.fragments;
    report["files"] = written;
    if (!args.json_path.empty()) output.write(args.json_path, report.dump());
    output.commit();
    if (!global.quiet) {
        out << "crackle export: " << preset.name << " -> " << files.front().path.string() << " ("
            << b.pieces.triangles.size() << " triangles, " << b.pieces.fragments << " pieces"
            << (args.split_pieces ? " as separate nodes" : "") << ", " << b.maps.width << "×" << b.maps.height_px
            << " px maps, +Y up, metres)\n";
        print_times(out, times);
    }
    return 0;
}

} // namespace crackle::app
