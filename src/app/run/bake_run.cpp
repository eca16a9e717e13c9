#include "app/run/bake_run.hpp"

#include "app/run/report.hpp"
#include "app/run/run_budget.hpp"
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "io/mesh_files.hpp"
#include "io/resolution.hpp"
#include "render/bake.hpp"
#include "render/gl_context.hpp"

#include <cstdio>
#include <set>

namespace crackle::app {

Baked bake_pipeline(const RunPlan& plan, StepTimes& times, const std::string& shader_dir,
                    const PatternOptions& pattern) {
    if (!shader_dir.empty())
        for (const char* name : {"common.glsl", "bake.vert", "bake.frag", "id.frag", "fullscreen.vert", "ao.frag"})
            if (!std::filesystem::is_regular_file(std::filesystem::path(shader_dir) / name))
                throw InputError("--shader-dir " + shader_dir, std::string("no ") + name + " there",
                                 "point it at a copy of the shaders/ folder");
    Baked b;
    b.sim = obtain_simulation(plan, pattern, times);
    Timer step;
    b.pieces = post::build_pieces(b.sim.pattern, plan.post);
    times.emplace_back("post", step.seconds());
    progress_stage("bake");
    step.reset();
    render::GlContext context;
    times.emplace_back("gl_context", step.seconds());
    step.reset();
    render::BakeOptions options = plan.bake;
    const io::MapSize map = plan.map_request.on(b.pieces.tile_size); // a loaded pattern's own tile
    options.width = map.width;
    options.height = map.height;
    options.shader_dir = shader_dir;
    b.maps = render::bake(b.pieces, options, context);
    times.emplace_back("bake", step.seconds());
    times.emplace_back("bake.render", b.maps.render_seconds);
    times.emplace_back("bake.readback", b.maps.readback_seconds);
    times.emplace_back("bake.ambient_occlusion", b.maps.ao_seconds);
    return b;
}

OutputNames bake_names(const RunPlan& plan, const BakeOutputs& outputs, const std::string& variant, bool pattern_wins) {
    const NameFields fields{plan.output.preset_file, plan.seed, variant};
    if (!pattern_wins && !plan.output.name.empty())
        return OutputNames(plan.output.name, fields, plan.output.name_where);
    return OutputNames(outputs.name_pattern.empty() ? "{preset}" : outputs.name_pattern, fields, outputs.name_where);
}

Json bake_one(const RunPlan& plan, const BakeOutputs& outputs, const OutputNames& names, const std::string& shader_dir,
              const PatternOptions& pattern, StepTimes& times, Baked* keep) {
    Timer total, step;
    const std::vector<io::MapRequest>& requests = plan.output.maps;
    // Where the files go is checked before any work (issue 16: a bad --out was found only after
    // the whole simulation and bake).
    check_output_path(outputs.dir / (names.base() + ".png"), "--out");
    if (!outputs.json_path.empty()) check_output_path(outputs.json_path, "--json");
    const RunBudget budget(plan, "the bake of " + names.base());
    const ProgressPlan progress(progress_stages(plan));
    Baked b = bake_pipeline(plan, times, shader_dir, pattern);
    progress_stage("encode");

    double encode = 0;
    const std::vector<io::EncodedMap> maps = io::encode_maps(b.maps, requests, plan.output.exr, &encode);
    times.emplace_back("encode", encode);
    progress_stage("write");
    AtomicOutput output;
    Json files = Json::array();
    std::set<std::filesystem::path> written;
    auto write = [&](const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
        // A mesh's .gltf/.obj maps are the bake's own files: written once.
        if (!written.insert(path.lexically_normal()).second) return;
        output.write(path, bytes);
        files.push_back(path.string());
    };
    for (const io::EncodedMap& m : maps)
        write(names.map_file(outputs.dir, m), m.bytes);
    for (const std::string& format : outputs.meshes) {
        step.reset();
        const std::filesystem::path file = outputs.dir / (names.base() + "." + format);
        for (io::OutputFile& f :
             io::mesh_files(b.pieces, b.maps, maps, file, io::MeshFileOptions{format, outputs.split_pieces}))
            write(f.path, f.bytes);
        times.emplace_back("mesh." + format, step.seconds());
    }
    times.emplace_back("total", total.seconds());

    Json report = simulation_report(b.sim, times);
    report["command"] = "bake";
    report["size"] = std::max(b.maps.width, b.maps.height_px);
    report["width"] = b.maps.width;
    report["height"] = b.maps.height_px;
    report["displacement_scale_m"] = b.maps.height_scale;
    Json chosen = Json::array();
    for (const io::MapRequest& m : requests)
        chosen.push_back(m.name + "=" + std::to_string(m.bits));
    report["maps"] = chosen;
    report["files"] = files;
    if (!outputs.variant_key.empty()) report["variant_key"] = outputs.variant_key;
    if (!outputs.json_path.empty()) output.write(outputs.json_path, report.dump());
    // Last: a report beside the maps says the whole set is in place.
    if (outputs.report_beside) output.write(outputs.dir / (names.base() + ".json"), report.dump());
    output.commit();
    if (keep) *keep = std::move(b);
    return report;
}

std::optional<std::pair<int, int>> parse_map_size(const std::string& text) {
    int w = 0, h = 0;
    char x = 0, extra = 0;
    const int n = std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra);
    auto ok = [](int side) { return side >= 16 && side <= 16384; };
    if (n == 1 && ok(w)) return std::make_pair(w, 0);
    if (n == 3 && (x == 'x' || x == 'X') && ok(w) && ok(h)) return std::make_pair(w, h);
    return std::nullopt;
}

io::PresetRequest with_bake_flags(io::PresetRequest request, const BakeFlags& flags) {
    auto flag = [&](const char* key, Value value, const char* name, std::size_t at) {
        request.flags.push_back({key, std::move(value), name, at});
    };
    if (flags.preview) { // under every --set: a value the user sets wins over the quick look's
        flag("bake.samples", std::int64_t{2}, "--preview", 0);
        flag("bake.size", std::int64_t{512}, "--preview", 0);
    }
    if (!flags.maps.empty()) flag("bake.maps", flags.maps, "--maps", flags.at);
    if (!flags.bit_depth.empty()) flag("bake.bit_depth", flags.bit_depth, "--bit-depth", flags.at);
    if (!flags.size.empty()) {
        const auto parsed = parse_map_size(flags.size);
        if (!parsed)
            throw InputError("--size " + flags.size, "not a map size",
                             "give the longer side in pixels (2048) or width x height (2048x1024), 16 to 16384 each");
        flag("bake.size", std::int64_t{parsed->first}, "--size", static_cast<std::size_t>(-1));
        flag("bake.size_v", std::int64_t{parsed->second}, "--size", static_cast<std::size_t>(-1));
    }
    return request;
}

} // namespace crackle::app
