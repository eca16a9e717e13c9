#include "io/texture_set.hpp"

#include "io/map_set.hpp"

namespace crackle::io {

std::vector<EncodedMap> encode_texture_set(const render::TextureSet& s, bool exr, double* seconds) {
    return encode_maps(s, parse_map_requests(default_maps(), default_bit_depths(), "", ""), exr, seconds);
}

EncodedMap encode_map(const render::TextureSet& set, const std::string& suffix) {
    // At the default depth of a bake, so the bytes match encode_texture_set's.
    const std::vector<MapRequest> request = parse_map_requests(suffix, default_bit_depths(), "", "");
    return encode_maps(set, request, false).front();
}

EncodedMap encode_orm(const render::TextureSet& set) {
    return encode_map(set, "ORM");
}

std::filesystem::path map_path(const std::filesystem::path& dir, const std::string& name, const EncodedMap& map) {
    return dir / (name + "_" + map.suffix + "." + map.extension);
}

} // namespace crackle::io
