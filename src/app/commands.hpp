#pragma once
/// @file The subcommands, free of CLI parsing (cli.cpp maps arguments onto these).

#include "io/preset.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

/// Options every command shares.
struct GlobalOptions {
    bool quiet = false;
};

int presets_list(std::ostream& out);
int presets_show(const io::PresetRequest& request, std::ostream& out);
int presets_doc(std::ostream& out);

struct MeshArgs {
    io::PresetRequest preset;
    std::string obj_path;  ///< "" = no OBJ
    std::string json_path; ///< "" = no report file
};

/// `crackle mesh`: discretize the preset's surface and report mesh figures.
int mesh_command(const MeshArgs& args, const GlobalOptions& global, std::ostream& out);

struct SimulateArgs {
    io::PresetRequest preset;
    std::string json_path;   ///< report (design.md field names)
    std::string events_path; ///< CSV of fracture events
    std::string png_path;    ///< quick preview of the crack pattern in texture space
    int png_size = 512;
    std::string save_path; ///< --save: the crack pattern file (bake/export --pattern read it)
    bool no_cache = false; ///< --no-cache: do not store the pattern in the cache
};

/// `crackle simulate`: grow and crack the preset's surface, report the pattern statistics.
int simulate_command(const SimulateArgs& args, const GlobalOptions& global, std::ostream& out);

struct BakeArgs {
    io::PresetRequest preset;
    std::string size;       ///< --size N or WxH ("" = bake.size)
    bool preview = false;   ///< --preview: 512 px, 2 samples
    bool watch = false;     ///< --watch: re-bake the preview whenever the preset file changes
    std::string shader_dir; ///< read GLSL from here instead of the embedded copies
    std::string out_dir;    ///< "" = out/
    std::string json_path;
    std::string pattern_path;        ///< --pattern: bake this crack pattern file, no simulation
    bool no_cache = false;           ///< --no-cache: neither read nor fill the pattern cache
    std::string maps;                ///< --maps (bake.maps)
    std::string bit_depth;           ///< --bit-depth (bake.bit_depth)
    std::string name;                ///< --name: the output name pattern (bake.name)
    std::vector<std::string> meshes; ///< --mesh glb,gltf,obj: meshes beside the maps
    bool split_pieces = false;       ///< --pieces: one mesh node per piece
    std::string seeds;               ///< --seeds 1-100,200: one bake per seed (a batch)
    std::string shard;               ///< --shard i/N: this slice of the seeds
};

/// `crackle bake`: the whole pipeline to a texture set.
int bake_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out);

struct ExportArgs {
    io::PresetRequest preset;
    std::string format = "glb"; ///< obj | gltf | glb
    std::string out_path;       ///< "" = out/<name>.<format>
    std::string size;           ///< --size N or WxH ("" = bake.size)
    std::string json_path;
    std::string shader_dir;
    std::string pattern_path;
    bool no_cache = false;
    bool split_pieces = false; ///< --pieces: one node / object per piece
};

/// `crackle export`: the piece mesh as OBJ or glTF with its PBR maps.
int export_command(const ExportArgs& args, const GlobalOptions& global, std::ostream& out);

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
