// tinygltf in its own translation unit (it pulls in nlohmann::json).
#include "core/error.hpp"
#include "io/mesh_export.hpp"

#include <cstring>
#include <sstream>
#include <tiny_gltf.h>

namespace crackle::io {

namespace {

/// Appends raw bytes to the buffer (4-byte aligned) and returns a new buffer view's index.
int add_view(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
    auto& buffer = model.buffers[0].data;
    while (buffer.size() % 4 != 0)
        buffer.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), p, p + bytes);
    model.bufferViews.push_back(view);
    return static_cast<int>(model.bufferViews.size() - 1);
}

int add_accessor(tinygltf::Model& model, int view, int component, std::size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
}

/// Keeps tinygltf from re-encoding or embedding images given by URI.
bool keep_image_uri(const std::string*, const std::string*, const tinygltf::Image*, bool, std::string*, void*) {
    return false;
}

} // namespace

std::vector<std::uint8_t> gltf_bytes(const ExportMesh& mesh, const MaterialMaps& maps, bool binary) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "crackle";
    model.buffers.resize(1);
    const std::size_t n = mesh.positions.size() / 3;

    // === Geometry
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    const int pos = add_accessor(
        model, add_view(model, mesh.positions.data(), 4 * mesh.positions.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC3);
    model.accessors[static_cast<std::size_t>(pos)].minValues = {mesh.min[0], mesh.min[1], mesh.min[2]};
    model.accessors[static_cast<std::size_t>(pos)].maxValues = {mesh.max[0], mesh.max[1], mesh.max[2]};
    prim.attributes["POSITION"] = pos;
    prim.attributes["NORMAL"] =
        add_accessor(model, add_view(model, mesh.normals.data(), 4 * mesh.normals.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC3);
    prim.attributes["TANGENT"] = add_accessor(
        model, add_view(model, mesh.tangents.data(), 4 * mesh.tangents.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC4);
    prim.attributes["TEXCOORD_0"] =
        add_accessor(model, add_view(model, mesh.uvs.data(), 4 * mesh.uvs.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                     TINYGLTF_COMPONENT_TYPE_FLOAT, n, TINYGLTF_TYPE_VEC2);
    prim.indices = add_accessor(
        model, add_view(model, mesh.indices.data(), 4 * mesh.indices.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
        TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, mesh.indices.size(), TINYGLTF_TYPE_SCALAR);

    // === Material: base colour, normal map (OpenGL convention, as glTF wants), packed ORM
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = TINYGLTF_TEXTURE_WRAP_REPEAT;
    sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
    model.samplers.push_back(sampler);
    auto add_texture = [&](const EncodedMap& map, const std::string& uri) {
        tinygltf::Image image;
        image.name = map.suffix;
        if (binary) {
            image.bufferView = add_view(model, map.bytes.data(), map.bytes.size(), 0);
            image.mimeType = "image/png";
        } else {
            image.uri = uri;
        }
        model.images.push_back(image);
        tinygltf::Texture tex;
        tex.sampler = 0;
        tex.source = static_cast<int>(model.images.size() - 1);
        model.textures.push_back(tex);
        return static_cast<int>(model.textures.size() - 1);
    };
    tinygltf::Material mat;
    mat.name = maps.name;
    mat.pbrMetallicRoughness.baseColorTexture.index = add_texture(maps.color, maps.color_uri);
    const int orm = add_texture(maps.orm, maps.orm_uri);
    mat.pbrMetallicRoughness.metallicRoughnessTexture.index = orm;
    mat.pbrMetallicRoughness.metallicFactor = 1.0; // scales the map's B channel, which is 0
    mat.pbrMetallicRoughness.roughnessFactor = 1.0;
    mat.normalTexture.index = add_texture(maps.normal, maps.normal_uri);
    mat.occlusionTexture.index = orm;
    model.materials.push_back(mat);
    prim.material = 0;

    tinygltf::Mesh m;
    m.name = maps.name;
    m.primitives.push_back(prim);
    model.meshes.push_back(m);
    tinygltf::Node node;
    node.name = maps.name;
    node.mesh = 0;
    model.nodes.push_back(node);
    tinygltf::Scene scene;
    scene.name = maps.name;
    scene.nodes.push_back(0);
    model.scenes.push_back(scene);
    model.defaultScene = 0;

    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(keep_image_uri, nullptr);
    std::ostringstream os;
    if (!writer.WriteGltfSceneToStream(&model, os, !binary, binary))
        throw NumericError("tinygltf failed to serialize the glTF model");
    const std::string s = os.str();
    return std::vector<std::uint8_t>(s.begin(), s.end());
}

} // namespace crackle::io
