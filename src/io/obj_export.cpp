// OBJ + MTL written as text; assimp (in this translation unit only) reads files back.
#include "core/error.hpp"
#include "io/mesh_export.hpp"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <charconv>
#include <functional>

namespace crackle::io {

namespace {

/// Shortest text that reads back as the same float.
void append_float(std::string& out, float x) {
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, ec == std::errc() ? end : buf);
}

void append_line(std::string& out, const char* key, const std::vector<float>& values, std::size_t i, std::size_t n) {
    out += key;
    for (std::size_t c = 0; c < n; ++c) {
        out += ' ';
        append_float(out, values[n * i + c]);
    }
    out += '\n';
}

/// The MTL. Which keys the importers read (checked with Blender 3.4.1's wm.obj_import; the others
/// from their MTL parsers):
///  - map_Kd colour; Pr/Pm and map_Pr/map_Pm (the PBR extension): Blender ≥ 3.4, three.js's
///    MTLLoader (map_Kd only: it builds Phong materials), assimp, tinyobjloader.
///  - the normal map: Blender (3.4 to 4.x) and Godot read only map_Bump/map_bump/bump, as a
///    tangent-space normal map (Godot 3 only lower-case map_bump, and without options); three.js,
///    assimp and tinyobjloader take `norm` as the normal map and map_bump as a height map. Both
///    keys are written: Blender ignores `norm`, and a reader that sees both keeps the normal map
///    in its normal slot.
///  - no legacy slots (map_Ns roughness, bump normal, map_Ka occlusion), and no occlusion map:
///    no key for it is read by these importers.
/// Colour spaces: no MTL option that sets one is read. Blender loads every map with its default
/// for the file (8-bit PNG: sRGB) and skips -cc and -imfchan; three.js decodes map_Kd as sRGB and
/// everything else as linear; assimp hands out paths. tinyobjloader's `-colorspace linear` would
/// become part of the file name in Blender and three.js (they keep unknown options in the path),
/// so the slot alone tells: colour is sRGB, roughness and normal are data (docs/exports.md tells
/// Blender users to switch those two to Non-Color, or to use glTF, whose importer does).
std::string mtl_text(const MaterialMaps& maps) {
    std::string mtl = "# crackle: PBR extension keys (Pr, Pm, map_Pr, norm); docs/exports.md\n";
    mtl += "newmtl " + maps.name + "\n";
    mtl += "Kd 1 1 1\n";       // the colour map alone sets the base colour
    mtl += "Ks 0.5 0.5 0.5\n"; // Blender: specular = mean(Ks) (0.5 = 4 % reflectance at normal incidence)
    mtl += "d 1\nillum 2\n";
    mtl += "Pr 1\nPm 0\n"; // scalars for readers without the maps; the roughness map overrides Pr
    mtl += "map_Kd " + maps.color_uri + "\n";
    if (!maps.roughness_uri.empty()) mtl += "map_Pr " + maps.roughness_uri + "\n";
    mtl += "norm " + maps.normal_uri + "\n";
    // -bm 1: Blender's Normal Map strength, which is 0 without it.
    mtl += "map_bump -bm 1 " + maps.normal_uri + "\n";
    return mtl;
}

/// The material slots import_summary reports, by assimp's names for them.
const std::pair<aiTextureType, const char*> TEXTURE_SLOTS[] = {
    {aiTextureType_DIFFUSE, "diffuse"},     {aiTextureType_NORMALS, "normals"},
    {aiTextureType_HEIGHT, "height"},       {aiTextureType_DIFFUSE_ROUGHNESS, "roughness"},
    {aiTextureType_METALNESS, "metalness"}, {aiTextureType_SHININESS, "shininess"},
    {aiTextureType_AMBIENT, "ambient"},     {aiTextureType_BASE_COLOR, "base_color"},
    {aiTextureType_LIGHTMAP, "lightmap"}};

} // namespace

std::pair<std::string, std::string> obj_text(const std::vector<ExportMesh>& meshes, const MaterialMaps& maps,
                                             const std::string& mtl_name) {
    std::string obj = "# crackle: +Y up, metres, faces counter-clockwise seen from outside; docs/exports.md\n";
    obj += "mtllib " + mtl_name + "\n";
    std::size_t base = 1; // OBJ indices are 1-based and run on across objects
    for (const ExportMesh& m : meshes) {
        obj += "o " + m.name + "\n";
        const std::size_t n = m.positions.size() / 3;
        for (std::size_t i = 0; i < n; ++i)
            append_line(obj, "v", m.positions, i, 3);
        // OBJ's vt origin is at the bottom: undo the glTF flip.
        for (std::size_t i = 0; i < n; ++i) {
            obj += "vt ";
            append_float(obj, m.uvs[2 * i]);
            obj += ' ';
            append_float(obj, 1.0f - m.uvs[2 * i + 1]);
            obj += '\n';
        }
        for (std::size_t i = 0; i < n; ++i)
            append_line(obj, "vn", m.normals, i, 3);
        obj += "usemtl " + maps.name + "\n";
        for (std::size_t f = 0; f < m.indices.size() / 3; ++f) {
            obj += 'f';
            for (std::size_t k = 0; k < 3; ++k) {
                const std::string id = std::to_string(base + m.indices[3 * f + k]);
                obj += ' ' + id + '/' + id + '/' + id;
            }
            obj += '\n';
        }
        base += n;
    }
    return {obj, mtl_text(maps)};
}

std::pair<std::string, std::string> obj_files(const ExportMesh& mesh, const MaterialMaps& maps,
                                              const std::string& mtl_name) {
    return obj_text({mesh}, maps, mtl_name);
}

ImportedSummary import_summary(const std::string& path) {
    ImportedSummary s;
    s.min.fill(std::numeric_limits<float>::max());
    s.max.fill(std::numeric_limits<float>::lowest());
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    if (!scene) throw InputError(path, std::string("assimp cannot read it: ") + importer.GetErrorString(), "re-export");
    s.meshes = scene->mNumMeshes;
    s.materials = scene->mNumMaterials;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* m = scene->mMeshes[i];
        s.vertices += m->mNumVertices;
        s.faces += m->mNumFaces;
        s.has_normals = m->HasNormals();
        s.has_uvs = m->HasTextureCoords(0);
        s.has_tangents = m->HasTangentsAndBitangents();
        const aiMaterial* mat = scene->mMaterials[m->mMaterialIndex];
        for (const auto& [type, slot] : TEXTURE_SLOTS) {
            aiString file;
            if (mat->GetTexture(type, 0, &file) == AI_SUCCESS) s.textures[slot] = file.C_Str();
        }
        for (unsigned v = 0; v < m->mNumVertices; ++v)
            for (unsigned c = 0; c < 3; ++c) {
                s.min[c] = std::min(s.min[c], m->mVertices[v][c]);
                s.max[c] = std::max(s.max[c], m->mVertices[v][c]);
            }
    }
    return s;
}

std::vector<ImportedMesh> import_meshes(const std::string& path) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    if (!scene) throw InputError(path, std::string("assimp cannot read it: ") + importer.GetErrorString(), "re-export");
    std::vector<ImportedMesh> out;
    std::function<void(const aiNode*)> visit = [&](const aiNode* node) {
        for (unsigned k = 0; k < node->mNumMeshes; ++k) {
            const aiMesh* m = scene->mMeshes[node->mMeshes[k]];
            ImportedMesh r;
            r.node = node->mName.C_Str();
            for (unsigned v = 0; v < m->mNumVertices; ++v)
                for (unsigned c = 0; c < 3; ++c) {
                    r.positions.push_back(m->mVertices[v][c]);
                    r.normals.push_back(m->HasNormals() ? m->mNormals[v][c] : 0.0f);
                }
            for (unsigned f = 0; f < m->mNumFaces; ++f)
                if (m->mFaces[f].mNumIndices == 3)
                    r.indices.insert(r.indices.end(), m->mFaces[f].mIndices, m->mFaces[f].mIndices + 3);
            out.push_back(std::move(r));
        }
        for (unsigned c = 0; c < node->mNumChildren; ++c)
            visit(node->mChildren[c]);
    };
    visit(scene->mRootNode);
    return out;
}

} // namespace crackle::io
