#include "io/texture_set.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"
#include "io/map_set.hpp"
#include "io/png.hpp"

#include <functional>
#include <future>

namespace crackle::io {

std::vector<EncodedMap> encode_texture_set(const render::TextureSet& s, bool exr, double* seconds) {
    return encode_maps(s, parse_map_requests(default_maps(), default_bit_depths(), "", ""), exr, seconds);
}

EncodedMap encode_orm(const render::TextureSet& s) {
    return encode_maps(s, {{"ORM", 8}}, false).front();
}

std::filesystem::path map_path(const std::filesystem::path& dir, const std::string& name, const EncodedMap& map) {
    return dir / (name + "_" + map.suffix + "." + map.extension);
}

} // namespace crackle::io
