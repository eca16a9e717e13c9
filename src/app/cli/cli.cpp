#include "app/cli/cli.hpp"

#include "app/bench/bench.hpp"
#include "app/bench/bench_scale.hpp"
#include "app/bench/bench_speedup.hpp"
#include "app/bench/study.hpp"
#include "app/commands/bake.hpp"
#include "app/commands/batch.hpp"
#include "app/commands/export.hpp"
#include "app/commands/mesh.hpp"
#include "app/commands/presets.hpp"
#include "app/commands/simulate.hpp"
#include "app/commands/watch.hpp"
#include "app/run/bake_run.hpp"
#include "core/budget.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/strings.hpp"
#include "io/random_preset.hpp"

#include <CLI/CLI.hpp>

#include <cstdlib>

#ifndef CRACKLE_VERSION
#define CRACKLE_VERSION "unknown"
#endif

namespace crackle::app {

namespace {

void add_preset_options(CLI::App* cmd, io::PresetRequest& request) {
    cmd->add_option("--set", request.overrides,
                    "Override a preset key, e.g. --set material.thickness=[0.02,0.02] (repeatable)")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    cmd->add_option("--seed", request.seed, "Seed of all randomness (overrides simulation.seed)")
        ->type_name("N")
        ->check(CLI::Validator(
            [](const std::string& text) {
                // A whole number 0 … 9·10^18 (simulation.seed's range), said in words, not as the
                // 309-digit double a generic range check prints.
                const bool digits =
                    !text.empty() && text.size() <= 19 && text.find_first_not_of("0123456789") == std::string::npos;
                if (digits && std::stoull(text) <= 9000000000000000000ULL) return std::string();
                return "expected a whole number from 0 to 9000000000000000000, got '" + text + "'";
            },
            "N"));
}

/// The PRESET a command runs (bark when none is given).
void add_preset_name(CLI::App* cmd, io::PresetRequest& request) {
    request.name_or_path = "bark";
    cmd->add_option("PRESET", request.name_or_path, "Built-in preset name or .toml path")->capture_default_str();
}

void add_pattern_options(CLI::App* cmd, std::string& pattern_path, bool& no_cache) {
    cmd->add_option("--pattern", pattern_path,
                    "Use this crack pattern file (from simulate --save) instead of simulating")
        ->type_name("FILE");
    cmd->add_flag("--no-cache", no_cache,
                  "Simulate even when the pattern cache holds this simulation (and do not store it)");
}

void add_output_options(CLI::App* cmd, std::string& maps, std::string& bit_depth, std::vector<std::string>& meshes,
                        bool& split_pieces) {
    cmd->add_option("--maps", maps,
                    "Maps to write (bake.maps): Color, NormalGL, NormalDX, Displacement, AmbientOcclusion, Roughness, "
                    "Mask, ID, ORM, MaskMap")
        ->type_name("LIST");
    cmd->add_option("--bit-depth", bit_depth, "Bits per channel (bake.bit_depth), e.g. Displacement=16,NormalGL=16")
        ->type_name("MAP=BITS,...");
    cmd->add_option("--mesh", meshes, "Also write the pieces as meshes beside the maps: glb, gltf, obj")
        ->delimiter(',')
        ->check(CLI::IsMember({"obj", "gltf", "glb"}))
        ->type_name("FORMATS");
    cmd->add_flag("--pieces", split_pieces, "Meshes: each piece its own node / object named piece_<fragment>");
}

/// Everything the command line fills, alive while the command runs.
struct Parsed {
    int verbosity = 0;
    bool quiet = false;
    std::string progress = "auto";
    double max_time = 0;
    std::string max_memory;
    CLI::Option* max_time_option = nullptr;
    CLI::Option* max_memory_option = nullptr;

    CLI::App *presets = nullptr, *mesh = nullptr, *simulate = nullptr, *bake = nullptr, *exp = nullptr,
             *batch = nullptr;
    io::PresetRequest show_request;
    std::uint64_t random_seed = 0;
    MeshArgs mesh_args;
    SimulateArgs sim_args;
    BakeArgs bake_args;
    ExportArgs export_args;
    BatchArgs batch_args;

    CLI::App *bench = nullptr, *bench_study = nullptr, *bench_speedup = nullptr, *bench_scale = nullptr,
             *bench_micro = nullptr;
    BenchArgs bench_args;
    StudyArgs study_args;
    std::string study_out, baseline;
    bool no_charts = false;
};

void add_global_options(CLI::App& app, Parsed& p) {
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("crackle ") + CRACKLE_VERSION);
    app.add_flag("-v,--verbose", p.verbosity, "More messages (repeat for debug output)");
    app.add_flag("-q,--quiet", p.quiet, "Only errors; no progress bars or summaries");
    app.add_option("--progress", p.progress,
                   "Progress on stderr: auto (a bar on a terminal), bar, json (a line a second, for farms) or "
                   "none; default $CRACKLE_PROGRESS, else auto")
        ->envname("CRACKLE_PROGRESS")
        ->check(CLI::Validator(progress_mode_check, "MODE"));
    p.max_time_option =
        app.add_option("--max-time", p.max_time,
                       "Seconds a simulation, bake or export (each variant of a batch) may run; past it the run "
                       "stops with exit 2 and writes nothing. Default $CRACKLE_MAX_TIME, else no limit")
            ->envname("CRACKLE_MAX_TIME")
            ->check(CLI::Range(0.001, 1.0e9));
    p.max_memory_option =
        app.add_option("--max-memory", p.max_memory,
                       "Memory a run may use (512M, 8G): a run estimated to need more is refused, one that "
                       "grows past it stops with exit 2. Default $CRACKLE_MAX_MEMORY, else 90 % of the machine's "
                       "(or its control group's) memory")
            ->envname("CRACKLE_MAX_MEMORY")
            ->check(CLI::Validator(memory_size_check, "SIZE"));
    // Global flags anywhere: `crackle bake mud -q` as well as `crackle -q bake mud` (options a
    // subcommand does not know fall through to its parent; subcommands inherit the setting).
    app.fallthrough();
}

CLI::Validator map_size_check() {
    return CLI::Validator(
        [](const std::string& text) {
            return parse_map_size(text) ? std::string()
                                        : "expected the longer side in pixels (2048) or width x height (2048x1024), "
                                          "16 to 16384 each";
        },
        "N|WxH");
}

void add_presets(CLI::App& app, Parsed& p) {
    CLI::App* presets = p.presets = app.add_subcommand("presets", "List, show or document presets");
    presets->require_subcommand(1);
    presets->add_subcommand("list", "List the built-in presets");
    CLI::App* show = presets->add_subcommand("show", "Print a preset fully resolved, defaults included");
    show->add_option("NAME", p.show_request.name_or_path, "Built-in preset name or path to a .toml file")->required();
    add_preset_options(show, p.show_request);
    presets->add_subcommand("doc", "Print the preset reference (docs/presets.md) in Markdown");
    CLI::App* random = presets->add_subcommand(
        "random", "Print a random in-range preset (every key may be drawn; scripts/soak runs hundreds)");
    random->add_option("SEED", p.random_seed, "Which preset: the same seed gives the same text")->required();
}

void add_mesh(CLI::App& app, Parsed& p) {
    CLI::App* mesh = p.mesh = app.add_subcommand("mesh", "Discretize a preset's surface and report mesh quality");
    add_preset_name(mesh, p.mesh_args.preset);
    mesh->add_option("--obj", p.mesh_args.obj_path, "Write the surface mesh as Wavefront OBJ");
    mesh->add_option("--json", p.mesh_args.json_path, "Write the report as JSON");
    add_preset_options(mesh, p.mesh_args.preset);
}

void add_simulate(CLI::App& app, Parsed& p) {
    CLI::App* simulate = p.simulate =
        app.add_subcommand("simulate", "Grow and crack a preset's surface; report the crack pattern");
    add_preset_name(simulate, p.sim_args.preset);
    simulate->add_option("--json", p.sim_args.json_path, "Write the report (pattern statistics, timings) as JSON");
    simulate->add_option("--events", p.sim_args.events_path, "Write the fracture events as CSV");
    simulate->add_option("--save", p.sim_args.save_path,
                         "Write the crack pattern to this file (bake and export read it with --pattern)");
    simulate->add_flag("--no-cache", p.sim_args.no_cache,
                       "Do not store the pattern in the cache (a later bake of the same simulation would reuse it)");
    simulate->add_option("--png", p.sim_args.png_path, "Write a quick preview of the crack pattern in texture space");
    simulate->add_option("--png-size", p.sim_args.png_size, "Preview size in pixels")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    add_preset_options(simulate, p.sim_args.preset);
}

void add_bake(CLI::App& app, Parsed& p) {
    CLI::App* bake = p.bake = app.add_subcommand("bake", "Run the whole pipeline and bake the texture set (PNG maps)");
    add_preset_name(bake, p.bake_args.preset);
    bake->add_option("--size", p.bake_args.size,
                     "Texture size in pixels: the longer side (2048), or width x height (2048x1024); overrides "
                     "bake.size")
        ->check(map_size_check());
    bake->add_option("--out", p.bake_args.out_dir, "Output folder (default: out)");
    bake->add_option("--json", p.bake_args.json_path, "Write the report as JSON");
    bake->add_flag("--preview", p.bake_args.preview, "Quick look: 512 px, 2 samples");
    bake->add_flag("--watch", p.bake_args.watch,
                   "Re-bake the preview whenever the preset file is saved; errors are shown and the watch goes "
                   "on; Ctrl-C stops");
    bake->add_option("--shader-dir", p.bake_args.shader_dir,
                     "Read the GLSL shaders from this folder (while editing them)");
    add_pattern_options(bake, p.bake_args.pattern_path, p.bake_args.no_cache);
    add_output_options(bake, p.bake_args.maps, p.bake_args.bit_depth, p.bake_args.meshes, p.bake_args.split_pieces);
    bake->add_option("--name", p.bake_args.name,
                     "Output name pattern with {preset}, {seed}, {variant}, {map}, e.g. {preset}_{seed}_{map} "
                     "(overrides bake.name)");
    bake->add_option("--seeds", p.bake_args.seeds, "Bake one variant per seed: 1-100, or a list 1,5,9-12")
        ->type_name("LIST");
    bake->add_option("--shard", p.bake_args.shard,
                     "Bake only slice i of N of the seeds (i/N, 1-based); under Slurm or Kubernetes the slice "
                     "comes from their variables (docs/farm.md)")
        ->type_name("i/N");
    add_preset_options(bake, p.bake_args.preset);
}

void add_export(CLI::App& app, Parsed& p) {
    CLI::App* exp = p.exp = app.add_subcommand("export", "Export the cracked pieces as a mesh with PBR maps");
    add_preset_name(exp, p.export_args.preset);
    exp->add_option("--format", p.export_args.format, "obj, gltf or glb")
        ->check(CLI::IsMember({"obj", "gltf", "glb"}))
        ->capture_default_str();
    exp->add_option("--out", p.export_args.out_path, "Output file (default: out/<name>.<format>)");
    exp->add_option("--size", p.export_args.size, "Map size in pixels: N or WxH (overrides bake.size)")
        ->check(map_size_check());
    exp->add_option("--json", p.export_args.json_path, "Write the report as JSON");
    exp->add_option("--shader-dir", p.export_args.shader_dir, "Read the GLSL shaders from this folder");
    add_pattern_options(exp, p.export_args.pattern_path, p.export_args.no_cache);
    exp->add_flag("--pieces", p.export_args.split_pieces,
                  "Write each piece as its own node / object named piece_<fragment> (like Cell Fracture)");
    add_preset_options(exp, p.export_args.preset);
}

void add_batch(CLI::App& app, Parsed& p) {
    CLI::App* batch = p.batch = app.add_subcommand(
        "batch", "Bake every variant of a manifest (JSON Lines or TOML), or one shard of it; reruns skip finished "
                 "variants (docs/farm.md)");
    batch->add_option("MANIFEST", p.batch_args.manifest, "The manifest: .jsonl or .toml")->required();
    batch->add_option("--out", p.batch_args.out_dir, "Output folder (default: out)");
    batch
        ->add_option("--shard", p.batch_args.shard,
                     "Run slice i of N (i/N, 1-based); N alone takes i from Slurm's or Kubernetes' variables")
        ->type_name("i/N");
    batch->add_flag("--merge", p.batch_args.merge,
                    "Merge the shards' summaries into batch-summary.json and check every variant is done");
    batch->add_flag("--list", p.batch_args.list,
                    "Print the shard's variants (index, name, preset, seed); bake nothing");
    batch->add_option("--size", p.batch_args.size, "Map size for every variant: N or WxH")->check(map_size_check());
    batch->add_option("--set", p.batch_args.overrides, "Override a preset key for every variant (before its own set)")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    batch->add_option("--shader-dir", p.batch_args.shader_dir, "Read the GLSL shaders from this folder");
    add_output_options(batch, p.batch_args.maps, p.batch_args.bit_depth, p.batch_args.meshes,
                       p.batch_args.split_pieces);
    batch->add_flag("--no-cache", p.batch_args.no_cache, "Simulate every variant even when the cache holds it");
}

void add_bench(CLI::App& app, Parsed& p) {
    CLI::App* bench = p.bench = app.add_subcommand(
        "bench", "The speed-vs-accuracy study (CSV and charts), this build against another, cost against size, or "
                 "named speed micro-benchmarks");
    p.bench_study = bench->add_subcommand("study", "The speed-vs-accuracy study (the default: `crackle bench`)");
    p.bench_speedup = bench->add_subcommand("speedup", "This build against --baseline, same runs interleaved");
    p.bench_scale =
        bench->add_subcommand("scale", "Cost against tile area and against refinement, charted (docs/benchmarks.md)");
    p.bench_micro = bench->add_subcommand("micro", "Speed micro-benchmarks: " + join(bench_scenes(), ", "));
    p.bench_micro->add_option("NAME", p.bench_args.scenes, "Which (default: all): " + join(bench_scenes(), ", "));
    for (CLI::App* sub : {p.bench_study, p.bench_speedup, p.bench_scale, p.bench_micro})
        sub->fallthrough(); // the options below belong to `bench`, written before or after the word
    // The form before the subcommands: `crackle bench solve local` runs those micro-benchmarks.
    bench->add_option("MICRO", p.bench_args.scenes, "Same as `bench micro NAME...` (the older form)");
    bench->add_option("--baseline", p.baseline,
                      "bench speedup, bench scale: the crackle executable to compare with (scripts/bench-baseline REV "
                      "builds one)");
    bench->add_flag("--quick", p.bench_args.quick, "A small subset (the study in about a minute; what CI runs)");
    bench->add_option("--out", p.study_out, "Output folder (study: runs.csv, points.csv, charts; default: bench)");
    bench
        ->add_option("--methods", p.study_args.methods,
                     "Study methods (comma-separated): " + join(study_methods(), ", ") + " (default: all)")
        ->delimiter(',');
    bench
        ->add_option("--scenes", p.study_args.scenes,
                     "Study scenes (comma-separated): " + join(study_scenes(), ", ") + " (default: all)")
        ->delimiter(',');
    bench
        ->add_option(
            "--seeds", p.study_args.seeds,
            "Seeds per point (default 3; 1 with --quick); with --make-reference, the reference's seeds (default 8)")
        ->check(CLI::Range(1, 50));
    bench->add_option("--time-limit", p.study_args.time_limit, "Seconds per run before it is stopped (default 600)")
        ->check(CLI::Range(1.0, 86400.0));
    bench->add_option("--reference", p.study_args.reference, "Read the reference from this file (default: built in)");
    bench->add_flag("--make-reference", p.study_args.make_reference,
                    "Run the reference runs and write reference.json into --out");
    bench->add_flag("--no-charts", p.no_charts, "Write the CSVs only (no python3/matplotlib needed)");
}

/// Messages, progress and the run budget, from the global options.
void apply_global_options(const Parsed& p, std::ostream& err) {
    log::set_stream(&err);
    log::set_level(p.quiet            ? log::Level::Error
                   : p.verbosity >= 2 ? log::Level::Debug
                   : p.verbosity == 1 ? log::Level::Info
                                      : log::Level::Warn);
    set_progress_enabled(!p.quiet);
    set_progress_mode(parse_progress_mode(p.progress).value_or(ProgressMode::Auto));
    BudgetLimits limits;
    // Messages name the option, and the variable when it is set (CLI11 lets the option win).
    if (p.max_time_option->count() > 0) {
        limits.seconds = p.max_time;
        limits.time_source = std::getenv("CRACKLE_MAX_TIME") ? "--max-time or $CRACKLE_MAX_TIME" : "--max-time";
    }
    if (p.max_memory_option->count() > 0) {
        limits.bytes = parse_memory_size(p.max_memory).value_or(0);
        limits.memory_source =
            std::getenv("CRACKLE_MAX_MEMORY") ? "--max-memory or $CRACKLE_MAX_MEMORY" : "--max-memory";
    }
    set_budget_limits(limits);
}

int run_bench(Parsed& p, std::ostream& out) {
    if (p.bench_speedup->parsed()) {
        SpeedupArgs speedup;
        speedup.baseline = p.baseline;
        speedup.quick = p.bench_args.quick;
        if (p.study_args.seeds > 0) speedup.seeds = p.study_args.seeds;
        speedup.out_dir = p.study_out;
        return speedup_command(speedup, out);
    }
    if (p.bench_scale->parsed()) {
        ScaleArgs scale;
        scale.baseline = p.baseline;
        scale.quick = p.bench_args.quick;
        if (p.study_args.seeds > 0) scale.seeds = p.study_args.seeds;
        scale.charts = !p.no_charts;
        scale.out_dir = p.study_out;
        return scale_command(scale, out);
    }
    if (p.bench_micro->parsed() || !p.bench_args.scenes.empty()) {
        p.bench_args.out_dir = p.study_out;
        return bench_command(p.bench_args, out);
    }
    p.study_args.quick = p.bench_args.quick;
    p.study_args.out_dir = p.study_out;
    p.study_args.charts = !p.no_charts;
    return study_command(p.study_args, out);
}

/// Runs the command the line named; its exit code.
int dispatch(Parsed& p, std::ostream& out, std::ostream& err) {
    const GlobalOptions global{p.quiet};
    if (p.presets->got_subcommand("list")) return presets_list(out);
    if (p.presets->got_subcommand("show")) return presets_show(p.show_request, out);
    if (p.presets->got_subcommand("doc")) return presets_doc(out);
    if (p.presets->got_subcommand("random")) {
        out << io::random_preset(p.random_seed);
        return 0;
    }
    if (p.mesh->parsed()) return mesh_command(p.mesh_args, global, out);
    if (p.simulate->parsed()) return simulate_command(p.sim_args, global, out);
    if (p.bake->parsed() && p.bake_args.watch) {
        std::atomic<bool> stop{false};
        install_interrupt_stop(stop);
        WatchControl control;
        control.stop = &stop;
        return watch_command(p.bake_args, global, out, err, control);
    }
    if (p.bake->parsed()) return bake_command(p.bake_args, global, out);
    if (p.exp->parsed()) return export_command(p.export_args, global, out);
    if (p.batch->parsed()) return batch_command(p.batch_args, global, out);
    if (p.bench->parsed()) return run_bench(p, out);
    return 0;
}

} // namespace

int run(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    CLI::App app{"crackle: grows surfaces, cracks them with fracture mechanics, and bakes the cracks into "
                 "texture maps and meshes.",
                 "crackle"};
    Parsed p;
    add_global_options(app, p);
    add_presets(app, p);
    add_mesh(app, p);
    add_simulate(app, p);
    add_bake(app, p);
    add_export(app, p);
    add_batch(app, p);
    add_bench(app, p);
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        out << app.help();
        return 0;
    } catch (const CLI::CallForAllHelp& e) {
        out << app.help("", CLI::AppFormatMode::All);
        return 0;
    } catch (const CLI::CallForVersion& e) {
        out << e.what() << "\n";
        return 0;
    } catch (const CLI::ParseError& e) {
        err << "error: " << e.what() << " (run 'crackle --help' for usage)\n";
        return 2;
    }
    apply_global_options(p, err);
    int code = 0;
    try {
        code = dispatch(p, out, err);
    } catch (const InputError& e) {
        err << "error: " << e.what() << "\n";
        code = 2;
    } catch (const NumericError& e) {
        err << "error: numeric failure: " << e.what() << "\n";
        code = 3;
    } catch (const std::exception& e) {
        err << "error: internal: " << e.what() << " (please report this with the command that caused it)\n";
        code = 1;
    }
    log::set_stream(nullptr);
    return code;
}

} // namespace crackle::app
