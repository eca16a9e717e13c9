// tinygltf in its own translation unit.
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

/// A tightly packed accessor over a new buffer view holding `values`.
template <typename T>
int add_accessor(tinygltf::Model& model, const std::vector<T>& values, int target, int component, int type,
                 std::size_t per_element) {
    tinygltf::Accessor a;
    a.bufferView = add_view(model, values.data(), sizeof(T) * values.size(), target);
    a.byteOffset = 0;
    a.componentType = component;
    a.count = values.size() / per_element;
    a.type = type;
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
}

/// Keeps tinygltf from re-encoding or embedding images given by URI.
bool keep_image_uri(const std::string*, const std::string*, const tinygltf::Image*, bool, std::string*, void*) {
    return false;
}

tinygltf::Primitive add_geometry(tinygltf::Model& model, const ExportMesh& mesh) {
    constexpr int ARRAY = TINYGLTF_TARGET_ARRAY_BUFFER, FLOAT = TINYGLTF_COMPONENT_TYPE_FLOAT;
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    const int pos = add_accessor(model, mesh.positions, ARRAY, FLOAT, TINYGLTF_TYPE_VEC3, 3);
    model.accessors[static_cast<std::size_t>(pos)].minValues = {mesh.min[0], mesh.min[1], mesh.min[2]};
    model.accessors[static_cast<std::size_t>(pos)].maxValues = {mesh.max[0], mesh.max[1], mesh.max[2]};
    prim.attributes["POSITION"] = pos;
    prim.attributes["NORMAL"] = add_accessor(model, mesh.normals, ARRAY, FLOAT, TINYGLTF_TYPE_VEC3, 3);
    prim.attributes["TANGENT"] = add_accessor(model, mesh.tangents, ARRAY, FLOAT, TINYGLTF_TYPE_VEC4, 4);
    prim.attributes["TEXCOORD_0"] = add_accessor(model, mesh.uvs, ARRAY, FLOAT, TINYGLTF_TYPE_VEC2, 2);
    prim.indices = add_accessor(model, mesh.indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER,
                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, 1);
    prim.material = 0;
    return prim;
}

/// Base colour, normal map (OpenGL convention, as glTF wants) and the packed ORM, which serves
/// as occlusion (R) and metallic-roughness (G, B) texture alike.
void add_material(tinygltf::Model& model, const MaterialMaps& maps, bool binary) {
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
}

/// tinygltf writes a .gltf's buffers only as data URIs (or as files of its own choosing): the
/// one data URI in the document (images are given by URI) becomes `uri`, which names the .bin.
std::string external_buffer(std::string gltf, const std::string& uri) {
    const std::string prefix = "\"data:application/octet-stream;base64,";
    const std::size_t begin = gltf.find(prefix);
    CRACKLE_ASSERT(begin != std::string::npos && gltf.find(prefix, begin + 1) == std::string::npos,
                   "the glTF JSON should hold exactly one data URI, the buffer's");
    const std::size_t end = gltf.find('"', begin + 1);
    return gltf.replace(begin, end + 1 - begin, "\"" + uri + "\"");
}

} // namespace

GltfFiles gltf_files(const std::vector<ExportMesh>& meshes, const MaterialMaps& maps, bool binary,
                     const std::string& bin_uri) {
    CRACKLE_ASSERT(!meshes.empty(), "a glTF export needs at least one mesh");
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "crackle";
    model.buffers.resize(1);

    // === One mesh and one node per ExportMesh, all sharing the material
    tinygltf::Scene scene;
    scene.name = maps.name;
    for (const ExportMesh& mesh : meshes) {
        tinygltf::Mesh m;
        m.name = mesh.name;
        m.primitives.push_back(add_geometry(model, mesh));
        model.meshes.push_back(m);
        tinygltf::Node node;
        node.name = mesh.name;
        node.mesh = static_cast<int>(model.meshes.size() - 1);
        // Blender's importer turns node extras into the object's custom properties.
        if (mesh.fragment)
            node.extras = tinygltf::Value(tinygltf::Value::Object{{"fragment", tinygltf::Value(*mesh.fragment)}});
        model.nodes.push_back(node);
        scene.nodes.push_back(static_cast<int>(model.nodes.size() - 1));
    }
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    add_material(model, maps, binary);

    // === Serialise: GLB with everything inside, or JSON with an external or embedded buffer
    GltfFiles out;
    const bool external = !binary && !bin_uri.empty();
    if (external) out.bin = model.buffers[0].data;
    tinygltf::TinyGLTF writer;
    writer.SetImageWriter(keep_image_uri, nullptr);
    std::ostringstream os;
    if (!writer.WriteGltfSceneToStream(&model, os, !binary, binary))
        throw NumericError("tinygltf failed to serialize the glTF model");
    const std::string s = external ? external_buffer(os.str(), bin_uri) : os.str();
    out.gltf.assign(s.begin(), s.end());
    return out;
}

std::vector<std::uint8_t> gltf_bytes(const ExportMesh& mesh, const MaterialMaps& maps, bool binary) {
    return gltf_files({mesh}, maps, binary, "").gltf;
}

} // namespace crackle::io
