#include "io/mesh_files.hpp"

#include "core/error.hpp"
#include "io/mesh_export.hpp"

#include <algorithm>

namespace crackle::io {

namespace {

std::vector<std::uint8_t> bytes_of(const std::string& text) {
    return {text.begin(), text.end()};
}

} // namespace

std::vector<OutputFile> mesh_files(const post::PieceMesh& pieces, const render::TextureSet& maps,
                                   const std::vector<EncodedMap>& encoded, const std::filesystem::path& file,
                                   const MeshFileOptions& options) {
    const std::string& format = options.format;
    if (format != "obj" && format != "gltf" && format != "glb")
        throw InputError(file.string(), "unknown mesh format '" + format + "'", "use obj, gltf or glb");
    if (pieces.triangles.empty())
        throw InputError(file.string(), "the piece mesh has no triangles", "check the preset");
    const std::filesystem::path dir = file.parent_path();
    const std::string stem = file.stem().string();
    const std::filesystem::path mesh_path = dir / (stem + "." + format);
    const std::vector<ExportMesh> meshes = export_meshes(pieces, options.split_pieces, stem);

    // === The referenced maps: the bake's own bytes where it has them, so that a bake and an
    // export into one folder write identical files under identical names.
    std::vector<OutputFile> map_files;
    auto use_map = [&](const std::string& suffix, std::string& uri) {
        const auto it = std::find_if(encoded.begin(), encoded.end(),
                                     [&](const EncodedMap& m) { return m.suffix == suffix && m.extension == "png"; });
        EncodedMap map = it != encoded.end() ? *it : encode_map(maps, suffix);
        uri = map_path("", stem, map).generic_string();
        map_files.push_back({map_path(dir, stem, map), map.bytes});
        return map;
    };
    MaterialMaps material;
    material.name = stem;
    material.color = use_map("Color", material.color_uri);
    material.normal = use_map("NormalGL", material.normal_uri);

    std::vector<OutputFile> files;
    if (format == "obj") {
        use_map("Roughness", material.roughness_uri);
        const std::string mtl_name = stem + ".mtl";
        const auto [obj, mtl] = obj_text(meshes, material, mtl_name);
        files.push_back({mesh_path, bytes_of(obj)});
        files.push_back({dir / mtl_name, bytes_of(mtl)});
    } else {
        material.orm = use_map("ORM", material.orm_uri);
        const bool binary = format == "glb";
        const std::string bin_name = stem + ".bin";
        GltfFiles gltf = gltf_files(meshes, material, binary, binary ? "" : bin_name);
        files.push_back({mesh_path, std::move(gltf.gltf)});
        if (!binary) files.push_back({dir / bin_name, std::move(gltf.bin)});
    }
    // A .glb carries its maps inside.
    if (format != "glb") files.insert(files.end(), map_files.begin(), map_files.end());
    return files;
}

} // namespace crackle::io
