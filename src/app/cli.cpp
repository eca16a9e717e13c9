#include "app/cli.hpp"

#include "app/bake_run.hpp"
#include "app/bench.hpp"
#include "app/bench_scale.hpp"
#include "app/bench_speedup.hpp"
#include "app/commands.hpp"
#include "app/study.hpp"
#include "app/watch.hpp"
#include "core/budget.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
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

} // namespace

int run(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
    CLI::App app{"crackle: grows surfaces, cracks them with fracture mechanics, and bakes the cracks into "
                 "texture maps and meshes.",
                 "crackle"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("crackle ") + CRACKLE_VERSION);
    int verbosity = 0;
    bool quiet = false;
    app.add_flag("-v,--verbose", verbosity, "More messages (repeat for debug output)");
    app.add_flag("-q,--quiet", quiet, "Only errors; no progress bars or summaries");
    std::string progress = "auto";
    app.add_option("--progress", progress,
                   "Progress on stderr: auto (a bar on a terminal), bar, json (a line a second, for farms) or "
                   "none; default $CRACKLE_PROGRESS, else auto")
        ->envname("CRACKLE_PROGRESS")
        ->check(CLI::Validator(progress_mode_check, "MODE"));
    double max_time = 0;
    std::string max_memory;
    CLI::Option* max_time_option =
        app.add_option("--max-time", max_time,
                       "Seconds a simulation, bake or export (each variant of a batch) may run; past it the run "
                       "stops with exit 2 and writes nothing. Default $CRACKLE_MAX_TIME, else no limit")
            ->envname("CRACKLE_MAX_TIME")
            ->check(CLI::Range(0.001, 1.0e9));
    CLI::Option* max_memory_option =
        app.add_option("--max-memory", max_memory,
                       "Memory a run may use (512M, 8G): a run estimated to need more is refused, one that "
                       "grows past it stops with exit 2. Default $CRACKLE_MAX_MEMORY, else 90 % of the machine's "
                       "(or its control group's) memory")
            ->envname("CRACKLE_MAX_MEMORY")
            ->check(CLI::Validator(memory_size_check, "SIZE"));
    // Global flags anywhere: `crackle bake mud -q` as well as `crackle -q bake mud` (options a
    // subcommand does not know fall through to its parent; subcommands inherit the setting).
    app.fallthrough();

    // === presets
    CLI::App* presets = app.add_subcommand("presets", "List, show or document presets");
    presets->require_subcommand(1);
    presets->add_subcommand("list", "List the built-in presets");
    io::PresetRequest show_request;
    CLI::App* show = presets->add_subcommand("show", "Print a preset fully resolved, defaults included");
    show->add_option("NAME", show_request.name_or_path, "Built-in preset name or path to a .toml file")->required();
    add_preset_options(show, show_request);
    presets->add_subcommand("doc", "Print the preset reference (docs/presets.md) in Markdown");
    std::uint64_t random_seed = 0;
    CLI::App* random = presets->add_subcommand(
        "random", "Print a random in-range preset (every key may be drawn; scripts/soak runs hundreds)");
    random->add_option("SEED", random_seed, "Which preset: the same seed gives the same text")->required();

    // === mesh
    MeshArgs mesh_args;
    mesh_args.preset.name_or_path = "bark";
    CLI::App* mesh = app.add_subcommand("mesh", "Discretize a preset's surface and report mesh quality");
    mesh->add_option("PRESET", mesh_args.preset.name_or_path, "Built-in preset name or .toml path")
        ->capture_default_str();
    mesh->add_option("--obj", mesh_args.obj_path, "Write the surface mesh as Wavefront OBJ");
    mesh->add_option("--json", mesh_args.json_path, "Write the report as JSON");
    add_preset_options(mesh, mesh_args.preset);

    // === simulate
    SimulateArgs sim_args;
    sim_args.preset.name_or_path = "bark";
    CLI::App* simulate = app.add_subcommand("simulate", "Grow and crack a preset's surface; report the crack pattern");
    simulate->add_option("PRESET", sim_args.preset.name_or_path, "Built-in preset name or .toml path")
        ->capture_default_str();
    simulate->add_option("--json", sim_args.json_path, "Write the report (pattern statistics, timings) as JSON");
    simulate->add_option("--events", sim_args.events_path, "Write the fracture events as CSV");
    simulate->add_option("--save", sim_args.save_path,
                         "Write the crack pattern to this file (bake and export read it with --pattern)");
    simulate->add_flag("--no-cache", sim_args.no_cache,
                       "Do not store the pattern in the cache (a later bake of the same simulation would reuse it)");
    simulate->add_option("--png", sim_args.png_path, "Write a quick preview of the crack pattern in texture space");
    simulate->add_option("--png-size", sim_args.png_size, "Preview size in pixels")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    add_preset_options(simulate, sim_args.preset);

    // === bake
    const CLI::Validator map_size_check(
        [](const std::string& text) {
            return parse_map_size(text) ? std::string()
                                        : "expected the longer side in pixels (2048) or width x height (2048x1024), "
                                          "16 to 16384 each";
        },
        "N|WxH");
    BakeArgs bake_args;
    bake_args.preset.name_or_path = "bark";
    CLI::App* bake = app.add_subcommand("bake", "Run the whole pipeline and bake the texture set (PNG maps)");
    bake->add_option("PRESET", bake_args.preset.name_or_path, "Built-in preset name or .toml path")
        ->capture_default_str();
    bake->add_option("--size", bake_args.size,
                     "Texture size in pixels: the longer side (2048), or width x height (2048x1024); overrides "
                     "bake.size")
        ->check(map_size_check);
    bake->add_option("--out", bake_args.out_dir, "Output folder (default: out)");
    bake->add_option("--json", bake_args.json_path, "Write the report as JSON");
    bake->add_flag("--preview", bake_args.preview, "Quick look: 512 px, 2 samples");
    bake->add_flag("--watch", bake_args.watch,
                   "Re-bake the preview whenever the preset file is saved; errors are shown and the watch goes "
                   "on; Ctrl-C stops");
    bake->add_option("--shader-dir", bake_args.shader_dir,
                     "Read the GLSL shaders from this folder (while editing them)");
    add_pattern_options(bake, bake_args.pattern_path, bake_args.no_cache);
    add_output_options(bake, bake_args.maps, bake_args.bit_depth, bake_args.meshes, bake_args.split_pieces);
    bake->add_option("--name", bake_args.name,
                     "Output name pattern with {preset}, {seed}, {variant}, {map}, e.g. {preset}_{seed}_{map} "
                     "(overrides bake.name)");
    bake->add_option("--seeds", bake_args.seeds, "Bake one variant per seed: 1-100, or a list 1,5,9-12")
        ->type_name("LIST");
    bake->add_option("--shard", bake_args.shard,
                     "Bake only slice i of N of the seeds (i/N, 1-based); under Slurm or Kubernetes the slice "
                     "comes from their variables (docs/farm.md)")
        ->type_name("i/N");
    add_preset_options(bake, bake_args.preset);

    // === export
    ExportArgs export_args;
    export_args.preset.name_or_path = "bark";
    CLI::App* exp = app.add_subcommand("export", "Export the cracked pieces as a mesh with PBR maps");
    exp->add_option("PRESET", export_args.preset.name_or_path, "Built-in preset name or .toml path")
        ->capture_default_str();
    exp->add_option("--format", export_args.format, "obj, gltf or glb")
        ->check(CLI::IsMember({"obj", "gltf", "glb"}))
        ->capture_default_str();
    exp->add_option("--out", export_args.out_path, "Output file (default: out/<name>.<format>)");
    exp->add_option("--size", export_args.size, "Map size in pixels: N or WxH (overrides bake.size)")
        ->check(map_size_check);
    exp->add_option("--json", export_args.json_path, "Write the report as JSON");
    exp->add_option("--shader-dir", export_args.shader_dir, "Read the GLSL shaders from this folder");
    add_pattern_options(exp, export_args.pattern_path, export_args.no_cache);
    exp->add_flag("--pieces", export_args.split_pieces,
                  "Write each piece as its own node / object named piece_<fragment> (like Cell Fracture)");
    add_preset_options(exp, export_args.preset);

    // === batch
    BatchArgs batch_args;
    CLI::App* batch = app.add_subcommand(
        "batch", "Bake every variant of a manifest (JSON Lines or TOML), or one shard of it; reruns skip finished "
                 "variants (docs/farm.md)");
    batch->add_option("MANIFEST", batch_args.manifest, "The manifest: .jsonl or .toml")->required();
    batch->add_option("--out", batch_args.out_dir, "Output folder (default: out)");
    batch
        ->add_option("--shard", batch_args.shard,
                     "Run slice i of N (i/N, 1-based); N alone takes i from Slurm's or Kubernetes' variables")
        ->type_name("i/N");
    batch->add_flag("--merge", batch_args.merge,
                    "Merge the shards' summaries into batch-summary.json and check every variant is done");
    batch->add_flag("--list", batch_args.list, "Print the shard's variants (index, name, preset, seed); bake nothing");
    batch->add_option("--size", batch_args.size, "Map size for every variant: N or WxH")->check(map_size_check);
    batch->add_option("--set", batch_args.overrides, "Override a preset key for every variant (before its own set)")
        ->type_name("KEY=VALUE")
        ->allow_extra_args(false);
    batch->add_option("--shader-dir", batch_args.shader_dir, "Read the GLSL shaders from this folder");
    add_output_options(batch, batch_args.maps, batch_args.bit_depth, batch_args.meshes, batch_args.split_pieces);
    batch->add_flag("--no-cache", batch_args.no_cache, "Simulate every variant even when the cache holds it");

    // === bench
    BenchArgs bench_args;
    StudyArgs study_args;
    std::string study_out;
    CLI::App* bench =
        app.add_subcommand("bench", "The speed-vs-accuracy study (CSV and charts), or a named speed micro-benchmark");
    bench->add_option(
        "MICRO", bench_args.scenes,
        "Speed micro-benchmarks instead of the study: solve, local, fem-remove, fem-split, mass-spring, bake; "
        "speedup (this build against --baseline), or scale (cost against tile area and refinement, charted)");
    std::string baseline;
    bench->add_option("--baseline", baseline,
                      "bench speedup, bench scale: the crackle executable to compare with (scripts/bench-baseline REV "
                      "builds one)");
    bench->add_flag("--quick", bench_args.quick, "A small subset (the study in about a minute; what CI runs)");
    bench->add_option("--out", study_out, "Output folder (study: runs.csv, points.csv, charts; default: bench)");
    bench
        ->add_option("--methods", study_args.methods,
                     "Study methods (comma-separated): mass-spring-regular, mass-spring-random, fem-remove, "
                     "fem-split, fem-split-tip, graph-fem (default: all)")
        ->delimiter(',');
    bench
        ->add_option(
            "--scenes", study_args.scenes,
            "Study scenes (comma-separated): bar, film, film-cylinder, film-sphere, arrest, mud, bark (default: all)")
        ->delimiter(',');
    bench
        ->add_option(
            "--seeds", study_args.seeds,
            "Seeds per point (default 3; 1 with --quick); with --make-reference, the reference's seeds (default 8)")
        ->check(CLI::Range(1, 50));
    bench->add_option("--time-limit", study_args.time_limit, "Seconds per run before it is stopped (default 600)")
        ->check(CLI::Range(1.0, 86400.0));
    bench->add_option("--reference", study_args.reference, "Read the reference from this file (default: built in)");
    bench->add_flag("--make-reference", study_args.make_reference,
                    "Run the reference runs and write reference.json into --out");
    bool no_charts = false;
    bench->add_flag("--no-charts", no_charts, "Write the CSVs only (no python3/matplotlib needed)");

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

    log::set_stream(&err);
    log::set_level(quiet            ? log::Level::Error
                   : verbosity >= 2 ? log::Level::Debug
                   : verbosity == 1 ? log::Level::Info
                                    : log::Level::Warn);
    set_progress_enabled(!quiet);
    set_progress_mode(parse_progress_mode(progress).value_or(ProgressMode::Auto));
    const GlobalOptions global{quiet};
    BudgetLimits limits;
    // Messages name the option, and the variable when it is set (CLI11 lets the option win).
    if (max_time_option->count() > 0) {
        limits.seconds = max_time;
        limits.time_source = std::getenv("CRACKLE_MAX_TIME") ? "--max-time or $CRACKLE_MAX_TIME" : "--max-time";
    }
    if (max_memory_option->count() > 0) {
        limits.bytes = parse_memory_size(max_memory).value_or(0);
        limits.memory_source =
            std::getenv("CRACKLE_MAX_MEMORY") ? "--max-memory or $CRACKLE_MAX_MEMORY" : "--max-memory";
    }
    set_budget_limits(limits);

    int code = 0;
    try {
        if (presets->got_subcommand("list"))
            code = presets_list(out);
        else if (presets->got_subcommand("show"))
            code = presets_show(show_request, out);
        else if (presets->got_subcommand("doc"))
            code = presets_doc(out);
        else if (presets->got_subcommand("random"))
            out << io::random_preset(random_seed);
        else if (mesh->parsed())
            code = mesh_command(mesh_args, global, out);
        else if (simulate->parsed())
            code = simulate_command(sim_args, global, out);
        else if (bake->parsed() && bake_args.watch) {
            std::atomic<bool> stop{false};
            install_interrupt_stop(stop);
            WatchControl control;
            control.stop = &stop;
            code = watch_command(bake_args, global, out, err, control);
        } else if (bake->parsed())
            code = bake_command(bake_args, global, out);
        else if (exp->parsed())
            code = export_command(export_args, global, out);
        else if (batch->parsed())
            code = batch_command(batch_args, global, out);
        else if (bench->parsed() && bench_args.scenes == std::vector<std::string>{"speedup"}) {
            SpeedupArgs speedup;
            speedup.baseline = baseline;
            speedup.quick = bench_args.quick;
            if (study_args.seeds > 0) speedup.seeds = study_args.seeds;
            speedup.out_dir = study_out;
            code = speedup_command(speedup, out);
        } else if (bench->parsed() && bench_args.scenes == std::vector<std::string>{"scale"}) {
            ScaleArgs scale;
            scale.baseline = baseline;
            scale.quick = bench_args.quick;
            if (study_args.seeds > 0) scale.seeds = study_args.seeds;
            scale.charts = !no_charts;
            scale.out_dir = study_out;
            code = scale_command(scale, out);
        } else if (bench->parsed() && !bench_args.scenes.empty()) {
            bench_args.out_dir = study_out;
            code = bench_command(bench_args, out);
        } else if (bench->parsed()) {
            study_args.quick = bench_args.quick;
            study_args.out_dir = study_out;
            study_args.charts = !no_charts;
            code = study_command(study_args, out);
        }
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
