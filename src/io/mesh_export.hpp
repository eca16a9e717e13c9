#pragma once
/// @file Exporting the piece mesh: OBJ + MTL through assimp, glTF 2.0 (.gltf with external
/// maps, or .glb with everything embedded) through tinygltf. assimp 5.2.5's glTF exporter
/// writes TEXCOORD_0 as VEC3 (a validator error), no tangents (a warning with normal maps)
/// and unused extension declarations, so glTF goes through tinygltf, which writes exactly
/// the accessors we describe.

#include "io/texture_set.hpp"
#include "post/pieces.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace crackle::io {

/// The PBR textures of the exported material: for .gltf and OBJ their file names (next to the
/// mesh file), for .glb their bytes.
struct MaterialMaps {
    std::string name = "crackle";
    EncodedMap color, normal, orm; ///< base colour (sRGB), OpenGL normal, occlusion/roughness/metallic
    std::string color_uri, normal_uri, orm_uri, roughness_uri, ao_uri;
};

/// The triangle data every exporter writes: world positions, normals, tangents (xyz + handedness w),
/// and UVs with glTF's origin (v flipped: (u, 1 − v)).
struct ExportMesh {
    std::vector<float> positions, normals, tangents, uvs;
    std::vector<std::uint32_t> indices;
    std::array<float, 3> min{}, max{};
};

/// Flattens the piece mesh and computes per-vertex tangents from the UVs (Lengyel's method,
/// Gram–Schmidt against the normal).
ExportMesh export_mesh(const post::PieceMesh& pieces);

/// glTF 2.0 bytes: JSON with an embedded geometry buffer and external maps (binary = false),
/// or a GLB container with geometry and maps inside (binary = true).
std::vector<std::uint8_t> gltf_bytes(const ExportMesh& mesh, const MaterialMaps& maps, bool binary);

/// OBJ and MTL text (assimp's OBJ exporter; the MTL names `mtl_name`).
std::pair<std::string, std::string> obj_files(const ExportMesh& mesh, const MaterialMaps& maps,
                                              const std::string& mtl_name);

/// Counts and bounds of a mesh file read back with assimp (round-trip tests and `export`'s check).
struct ImportedSummary {
    std::size_t meshes = 0, vertices = 0, faces = 0, materials = 0;
    bool has_normals = false, has_uvs = false, has_tangents = false;
    std::array<float, 3> min{}, max{};
};
ImportedSummary import_summary(const std::string& path);

} // namespace crackle::io
