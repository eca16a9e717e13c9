#include "app/options.hpp"
#include "app/pipeline.hpp"
#include "io/mesh_files.hpp"
#include "support/export_fixtures.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

using namespace crackle;

// A manual check's inputs, not a test: with CRACKLE_BLENDER_FILES=<folder> it writes the mud
// and bark presets, baked at 256 px, as .gltf, .glb and .obj, whole and split per piece, for
// tests/tools/blender_import.py (docs/exports.md). Without the variable it does nothing.
TEST_SUITE("io") {
    TEST_CASE("mesh files: the Blender check's files, written when CRACKLE_BLENDER_FILES names a folder") {
        const char* folder = std::getenv("CRACKLE_BLENDER_FILES");
        if (!folder) return;
        const auto gl = test::gl_context_or_skip();
        if (!gl) return;
        for (const std::string preset_name : {"mud", "bark"}) {
            const io::Preset preset = io::load_preset({preset_name, {"bake.size=256"}, -1});
            StepTimes times;
            const app::SimulationResult sim = app::run_simulation(preset, times);
            const post::PieceMesh pieces = post::build_pieces(sim.pattern, app::post_options(preset));
            const render::TextureSet maps = render::bake(pieces, app::bake_options(preset, pieces), *gl);
            const std::vector<io::EncodedMap> encoded = io::encode_texture_set(maps, false);
            for (const char* format : {"gltf", "glb", "obj"})
                for (bool split : {false, true}) {
                    const std::string stem = preset_name + (split ? "_split" : "");
                    test::write_files(
                        io::mesh_files(pieces, maps, encoded, std::filesystem::path(folder) / stem, {format, split}));
                }
            MESSAGE(preset_name << ": " << pieces.fragments << " fragments, " << pieces.triangles.size()
                                << " triangles -> " << std::string(folder));
        }
    }
}
