#pragma once
/// @file One mesh export as the list of files it consists of (the caller writes them): the mesh
/// file, for .gltf its .bin, for .gltf and .obj the maps it references, for OBJ the .mtl.
/// Conventions (axes, winding, MTL keys, per-piece mode): docs/exports.md.

#include "io/texture_set.hpp"
#include "post/pieces.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace crackle::io {

struct MeshFileOptions {
    std::string format = "glb"; ///< "obj" | "gltf" | "glb"
    bool split_pieces = false;  ///< one node / object per fragment (piece_<id>, crack_floor)
};

struct OutputFile {
    std::filesystem::path path;
    std::vector<std::uint8_t> bytes;
};

/// Every file of one mesh export to `file` (its extension is ignored; options.format decides):
/// the mesh file, for .gltf its .bin, for .gltf/.obj the maps it references (next to it, named
/// map_path(dir, stem, map)), for OBJ the .mtl. `encoded` are the bake's encoded maps
/// (encode_texture_set); maps it needs but cannot find there (ORM) it encodes from `maps`.
/// glTF references Color, NormalGL and ORM; OBJ Color, Roughness and NormalGL.
/// @throws InputError for an unknown format or a mesh without triangles.
std::vector<OutputFile> mesh_files(const post::PieceMesh& pieces, const render::TextureSet& maps,
                                   const std::vector<EncodedMap>& encoded, const std::filesystem::path& file,
                                   const MeshFileOptions& options);

} // namespace crackle::io
