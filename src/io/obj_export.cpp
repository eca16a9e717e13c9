// assimp in its own translation unit.
#include "core/error.hpp"
#include "io/mesh_export.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

namespace crackle::io {

std::pair<std::string, std::string> obj_files(const ExportMesh& mesh, const MaterialMaps& maps,
                                              const std::string& mtl_name) {
    // assimp 5.2.5's OBJ exporter crashes on a scene without materials: always give one.
    aiScene scene;
    scene.mRootNode = new aiNode();
    scene.mRootNode->mName = maps.name;
    scene.mMaterials = new aiMaterial*[1];
    scene.mNumMaterials = 1;
    auto* mat = new aiMaterial();
    scene.mMaterials[0] = mat;
    const aiString name(maps.name);
    mat->AddProperty(&name, AI_MATKEY_NAME);
    const aiString color(maps.color_uri), normal(maps.normal_uri), rough(maps.roughness_uri), ao(maps.ao_uri);
    mat->AddProperty(&color, AI_MATKEY_TEXTURE_DIFFUSE(0));
    mat->AddProperty(&normal, AI_MATKEY_TEXTURE_NORMALS(0));
    if (!maps.roughness_uri.empty()) mat->AddProperty(&rough, AI_MATKEY_TEXTURE_SHININESS(0));
    if (!maps.ao_uri.empty()) mat->AddProperty(&ao, AI_MATKEY_TEXTURE_AMBIENT(0));

    scene.mMeshes = new aiMesh*[1];
    scene.mNumMeshes = 1;
    auto* m = new aiMesh();
    scene.mMeshes[0] = m;
    m->mName = maps.name;
    m->mMaterialIndex = 0;
    m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    const unsigned n = static_cast<unsigned>(mesh.positions.size() / 3);
    m->mNumVertices = n;
    m->mVertices = new aiVector3D[n];
    m->mNormals = new aiVector3D[n];
    m->mTextureCoords[0] = new aiVector3D[n];
    m->mNumUVComponents[0] = 2;
    for (unsigned i = 0; i < n; ++i) {
        m->mVertices[i] = aiVector3D(mesh.positions[3 * i], mesh.positions[3 * i + 1], mesh.positions[3 * i + 2]);
        m->mNormals[i] = aiVector3D(mesh.normals[3 * i], mesh.normals[3 * i + 1], mesh.normals[3 * i + 2]);
        // OBJ's vt origin is at the bottom: undo the glTF flip.
        m->mTextureCoords[0][i] = aiVector3D(mesh.uvs[2 * i], 1.0f - mesh.uvs[2 * i + 1], 0.0f);
    }
    const unsigned faces = static_cast<unsigned>(mesh.indices.size() / 3);
    m->mNumFaces = faces;
    m->mFaces = new aiFace[faces];
    for (unsigned f = 0; f < faces; ++f) {
        aiFace& face = m->mFaces[f];
        face.mNumIndices = 3;
        face.mIndices = new unsigned[3];
        for (unsigned k = 0; k < 3; ++k)
            face.mIndices[k] = mesh.indices[3 * f + k];
    }
    scene.mRootNode->mMeshes = new unsigned[1];
    scene.mRootNode->mMeshes[0] = 0;
    scene.mRootNode->mNumMeshes = 1;

    Assimp::Exporter exporter;
    const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, "obj");
    if (!blob) throw NumericError(std::string("assimp could not export OBJ: ") + exporter.GetErrorString());
    std::string obj(static_cast<const char*>(blob->data), blob->size), mtl;
    for (const aiExportDataBlob* b = blob->next; b; b = b->next)
        if (std::string(b->name.C_Str()) == "mtl") mtl.assign(static_cast<const char*>(b->data), b->size);
    // The blob names its material library after itself; point it at our file name.
    const std::string key = "mtllib ";
    const auto pos = obj.find(key);
    if (pos != std::string::npos) {
        const auto end = obj.find('\n', pos);
        obj.replace(pos, end - pos, key + mtl_name);
    }
    return {obj, mtl};
}

ImportedSummary import_summary(const std::string& path) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    if (!scene) throw InputError(path, std::string("assimp cannot read it: ") + importer.GetErrorString(), "re-export");
    ImportedSummary s;
    s.meshes = scene->mNumMeshes;
    s.materials = scene->mNumMaterials;
    s.min = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
    s.max = {std::numeric_limits<float>::lowest(), std::numeric_limits<float>::lowest(),
             std::numeric_limits<float>::lowest()};
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const aiMesh* m = scene->mMeshes[i];
        s.vertices += m->mNumVertices;
        s.faces += m->mNumFaces;
        s.has_normals = m->HasNormals();
        s.has_uvs = m->HasTextureCoords(0);
        s.has_tangents = m->HasTangentsAndBitangents();
        for (unsigned v = 0; v < m->mNumVertices; ++v)
            for (int c = 0; c < 3; ++c) {
                s.min[static_cast<std::size_t>(c)] =
                    std::min(s.min[static_cast<std::size_t>(c)], m->mVertices[v][static_cast<unsigned>(c)]);
                s.max[static_cast<std::size_t>(c)] =
                    std::max(s.max[static_cast<std::size_t>(c)], m->mVertices[v][static_cast<unsigned>(c)]);
            }
    }
    return s;
}

} // namespace crackle::io
