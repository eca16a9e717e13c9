#pragma once
/// @file One bake, shared by `crackle bake`, its seed lists and `crackle batch`: the simulation
/// (or a reused pattern), the pieces, the maps chosen by bake.maps at bake.bit_depth, meshes on
/// request, and the report, all written as one atomic set (the report last, so a report on disk
/// means every file it lists is complete).

#include "app/run/naming.hpp"
#include "app/run/pattern_store.hpp"
#include "io/map_set.hpp"
#include "post/pieces.hpp"
#include "render/texture_set.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace crackle::app {

/// Everything a bake or export needs: the simulation, the pieces and the maps.
struct Baked {
    SimulationResult sim;
    post::PieceMesh pieces;
    render::TextureSet maps;
};

Baked bake_pipeline(const RunPlan& plan, StepTimes& times, const std::string& shader_dir,
                    const PatternOptions& pattern);

/// Where and what one bake writes.
struct BakeOutputs {
    std::filesystem::path dir = "out";
    std::string name_pattern;          ///< bake.name, a manifest name, or the default
    std::string name_where = "--name"; ///< where the pattern came from, for messages
    std::vector<std::string> meshes;   ///< "glb", "gltf", "obj" written beside the maps (bake --mesh)
    bool split_pieces = false;         ///< meshes: one node / object per piece
    std::string json_path;             ///< a copy of the report ("" = none)
    bool report_beside = false;        ///< also <dir>/<base>.json (batches: marks the variant done)
    std::string variant_key;           ///< stored in the report; a rerun skips a variant whose key matches
};

/// The names the bake will use: outputs.name_pattern when `pattern_wins` (a manifest's name),
/// else bake.name when set, else outputs.name_pattern, else "{preset}". Checked: throws
/// InputError before any work.
OutputNames bake_names(const RunPlan& plan, const BakeOutputs& outputs, const std::string& variant = "",
                       bool pattern_wins = false);

/// Runs one bake of a plan made with PlanRequest::bake and writes its files and report; returns
/// the report.
Json bake_one(const RunPlan& plan, const BakeOutputs& outputs, const OutputNames& names, const std::string& shader_dir,
              const PatternOptions& pattern, StepTimes& times, Baked* keep = nullptr);

/// "2048" → (2048, 0): the longer side; "2048x1024" → (2048, 1024). Empty optional when the text
/// is neither or a side is outside 16..16384 pixels.
std::optional<std::pair<int, int>> parse_map_size(const std::string& text);

/// The bake's own flags, as the command line gave them.
struct BakeFlags {
    std::string size = {};      ///< --size: "2048" or "2048x1024" (bake.size, bake.size_v)
    std::string maps = {};      ///< --maps (bake.maps)
    std::string bit_depth = {}; ///< --bit-depth (bake.bit_depth)
    bool preview = false;       ///< --preview: 512 px and 2 samples unless --set or --size say otherwise
    /// --maps and --bit-depth apply just before overrides[at] (batch: under each variant's own set).
    std::size_t at = static_cast<std::size_t>(-1);
};

/// The bake's flags as typed values of the keys they stand for (io::FlagValue), checked: --size
/// that is not a map size throws InputError.
io::PresetRequest with_bake_flags(io::PresetRequest request, const BakeFlags& flags);

} // namespace crackle::app
