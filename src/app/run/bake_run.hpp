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

Baked bake_pipeline(const io::Preset& preset, const RunPlan& plan, StepTimes& times, const std::string& shader_dir,
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
OutputNames bake_names(const io::Preset& preset, const BakeOutputs& outputs, const std::string& variant = "",
                       bool pattern_wins = false);

/// The maps bake.maps and bake.bit_depth ask for (checked: throws InputError naming the line).
std::vector<io::MapRequest> bake_maps(const io::Preset& preset);

/// Runs one bake and writes its files and report; returns the report.
Json bake_one(const io::Preset& preset, const BakeOutputs& outputs, const OutputNames& names,
              const std::string& shader_dir, const PatternOptions& pattern, StepTimes& times, Baked* keep = nullptr);

/// "2048" → (2048, 0): the longer side; "2048x1024" → (2048, 1024). Empty optional when the text
/// is neither or a side is outside 16..16384 pixels.
std::optional<std::pair<int, int>> parse_map_size(const std::string& text);

/// Applies the bake command's shortcuts (--preview, --size WxH) to a preset request.
io::PresetRequest with_bake_overrides(io::PresetRequest request, const std::string& size, bool preview);

/// The quick look's reduced model of a loaded preset (`bake --preview`): io::element_count's
/// preview count and what the method leaves out for a preview (MethodInfo::preview_overrides).
io::Preset preview_preset(const io::Preset& full);

} // namespace crackle::app
