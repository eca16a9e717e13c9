#pragma once
/// @file Which maps a bake writes and at what bit depth (bake.maps, bake.bit_depth; `--maps`,
/// `--bit-depth`), including the packed maps engines want: glTF's ORM (occlusion, roughness,
/// metallic) and Unity's HDRP/URP mask map (metallic, occlusion, detail mask, smoothness).

#include "io/texture_set.hpp"

#include <string>
#include <vector>

namespace crackle::io {

struct MapRequest {
    std::string name; ///< "Color", "NormalGL", ..., "ORM", "MaskMap"
    int bits = 8;     ///< 8 or 16 per channel
};

/// Every map name a bake can write, in the order they are written, and the default set.
const std::vector<std::string>& map_names();
const std::string& default_maps();
const std::string& default_bit_depths();

/// Parses "Color,NormalGL,Displacement" and "Displacement=16,Roughness=16". Throws InputError
/// naming `where_maps` or `where_bits` (a preset line or a flag) for an unknown map, a repeated
/// one, or a depth the map cannot take (colour and ID maps are 8-bit sRGB).
std::vector<MapRequest> parse_map_requests(const std::string& maps, const std::string& bit_depths,
                                           const std::string& where_maps, const std::string& where_bits);

/// Encodes the requested maps as PNG (and the displacement as a 32-bit float EXR when `exr`),
/// each on its own thread. Returns them in request order with the encoding time.
std::vector<EncodedMap> encode_maps(const render::TextureSet& set, const std::vector<MapRequest>& maps, bool exr,
                                    double* seconds = nullptr);

} // namespace crackle::io
