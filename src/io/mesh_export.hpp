#pragma once
/// @file Exporting the piece mesh: OBJ + MTL (written here, with the MTL's PBR extension keys),
/// glTF 2.0 (.gltf + .bin + maps, or .glb with everything inside) through tinygltf. assimp 5.2.5's
/// glTF exporter writes TEXCOORD_0 as VEC3 (a validator error), no tangents (a warning with normal
/// maps) and unused extension declarations, and its OBJ exporter only knows the legacy MTL slots,
/// so assimp is left to read files back. Conventions (axes, winding, files): docs/exports.md.

#include "io/texture_set.hpp"
#include "post/pieces.hpp"

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace crackle::io {

/// The PBR textures of the exported material: for .gltf and OBJ their file names (next to the
/// mesh file), for .glb their bytes.
struct MaterialMaps {
    std::string name = "crackle";
    EncodedMap color, normal, orm; ///< base colour (sRGB), OpenGL normal, occlusion/roughness/metallic
    std::string color_uri, normal_uri, orm_uri, roughness_uri, ao_uri; ///< ao_uri: unused (no MTL key reads it)
};

/// The triangle data every exporter writes, in the exchange frame: +Y up, metres, triangles
/// counter-clockwise seen from outside. Positions, normals, tangents (xyz along +u, and w = ±1 so
/// that w·(N × T) points up the image, where the OpenGL normal map's green points) and UVs with
/// glTF's origin (v flipped: (u, 1 − v)).
struct ExportMesh {
    std::string name = "crackle"; ///< glTF node and mesh, OBJ object
    std::optional<int> fragment;  ///< split export: the piece's fragment id (−1: crack floor)
    std::vector<float> positions, normals, tangents, uvs;
    std::vector<std::uint32_t> indices;
    std::array<float, 3> min{}, max{};
};

/// crackle's world is Z-up (plane in XY, trunk along Z); glTF and the engines are Y-up:
/// (x, y, z) ↦ (x, z, −y), a rotation by −90° about x (det +1: winding and handedness kept).
inline Vec3 to_y_up(const Vec3& p) {
    return {p.x(), p.z(), -p.y()};
}

/// Flattens the piece mesh into the exchange frame and computes per-vertex tangents from the
/// UVs (Lengyel's method, Gram–Schmidt against the normal).
ExportMesh export_mesh(const post::PieceMesh& pieces);

/// The meshes of one export: the whole piece mesh named `name` (split = false), or one mesh per
/// fragment named piece_<id> plus `crack_floor` for fragment −1 (split = true; groups without
/// triangles are left out). Split meshes have their own vertices, so their tangents see only
/// their own triangles.
std::vector<ExportMesh> export_meshes(const post::PieceMesh& pieces, bool split, const std::string& name);

/// A glTF export: the JSON (or the whole GLB) and, for .gltf with an external buffer, the .bin.
struct GltfFiles {
    std::vector<std::uint8_t> gltf, bin;
};

/// glTF 2.0 with one node per mesh (named after it, `extras: {"fragment": id}` when split).
/// binary: a GLB with geometry and maps inside. Otherwise JSON with external maps (the *_uri
/// fields) and the geometry in `bin`, referenced as `bin_uri`; an empty `bin_uri` embeds it as a
/// base64 data URI instead (the app's old path).
GltfFiles gltf_files(const std::vector<ExportMesh>& meshes, const MaterialMaps& maps, bool binary,
                     const std::string& bin_uri);

/// One mesh as a GLB (binary) or as a .gltf with its buffer embedded (see gltf_files).
std::vector<std::uint8_t> gltf_bytes(const ExportMesh& mesh, const MaterialMaps& maps, bool binary);

/// OBJ and MTL text: one `o` per mesh, faces v/vt/vn with OBJ's vt origin at the bottom; the MTL
/// (named `mtl_name` in the OBJ) names colour, roughness and normal maps with the PBR extension
/// keys (see obj_export.cpp for what each importer reads).
std::pair<std::string, std::string> obj_text(const std::vector<ExportMesh>& meshes, const MaterialMaps& maps,
                                             const std::string& mtl_name);
std::pair<std::string, std::string> obj_files(const ExportMesh& mesh, const MaterialMaps& maps,
                                              const std::string& mtl_name);

/// Counts and bounds of a mesh file read back with assimp (round-trip tests and `export`'s check).
struct ImportedSummary {
    std::size_t meshes = 0, vertices = 0, faces = 0, materials = 0;
    bool has_normals = false, has_uvs = false, has_tangents = false;
    std::array<float, 3> min{}, max{};
    std::map<std::string, std::string> textures; ///< slot ("diffuse", "normals", "roughness", ...) → file
};
ImportedSummary import_summary(const std::string& path);

/// One mesh of a file read back with assimp and no post-processing (no axis or winding changes).
struct ImportedMesh {
    std::string node;                      ///< the name of the node that holds it
    std::vector<float> positions, normals; ///< 3 per vertex
    std::vector<std::uint32_t> indices;    ///< 3 per triangle
};
std::vector<ImportedMesh> import_meshes(const std::string& path);

} // namespace crackle::io
