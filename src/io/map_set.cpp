#include "io/map_set.hpp"

#include "core/error.hpp"
#include "core/strings.hpp"
#include "core/timer.hpp"
#include "io/png.hpp"

#include <algorithm>
#include <cmath>
#include <future>

namespace crackle::io {

namespace {

/// How one map is made from the texture set: its channels, whether it may be 16-bit, and each
/// channel's value in [0, 1] at a pixel (`invert`: the stored value is max − quantized value,
/// so DirectX's green is the exact complement of OpenGL's at either depth).
struct MapKind {
    const char* name;
    int channels;
    bool may_be_16bit;
    int default_bits;
};

const MapKind KINDS[] = {
    {"Color", 3, false, 8},
    {"NormalGL", 3, true, 8},
    {"NormalDX", 3, true, 8},
    {"Displacement", 1, true, 16},
    {"AmbientOcclusion", 1, true, 8},
    {"Roughness", 1, true, 8},
    {"Mask", 1, true, 8},
    {"ID", 3, false, 8},
    {"ORM", 3, true, 8},
    {"MaskMap", 4, false, 8},
};

const MapKind* find_kind(const std::string& name) {
    for (const MapKind& k : KINDS)
        if (name == k.name) return &k;
    return nullptr;
}

double channel_value(const render::TextureSet& s, const std::string& map, std::size_t i, int c, bool& invert) {
    invert = false;
    const auto rgb = [&](const std::vector<std::uint8_t>& v) { return v[3 * i + static_cast<std::size_t>(c)] / 255.0; };
    const auto normal = [&] { return 0.5 * s.normal[3 * i + static_cast<std::size_t>(c)] + 0.5; };
    if (map == "Color") return rgb(s.color);
    if (map == "ID") return rgb(s.id);
    if (map == "NormalGL") return normal();
    if (map == "NormalDX") {
        // DirectX's green points down the image: the complement of OpenGL's.
        invert = c == 1;
        return normal();
    }
    if (map == "Displacement") return s.height[i] / s.height_scale;
    if (map == "AmbientOcclusion") return s.ao[i];
    if (map == "Roughness") return s.roughness[i];
    if (map == "Mask") return s.mask[i];
    if (map == "ORM") return c == 0 ? s.ao[i] : c == 1 ? s.roughness[i] : 0.0; // glTF: metallic 0
    // Unity's mask map: metallic, occlusion, detail mask (everywhere), smoothness.
    return c == 0 ? 0.0 : c == 1 ? s.ao[i] : c == 2 ? 1.0 : 1.0 - s.roughness[i];
}

template <class T> std::vector<T> samples(const render::TextureSet& s, const std::string& map, int channels) {
    constexpr double top = static_cast<double>(std::numeric_limits<T>::max());
    const std::size_t px = s.pixels(), n = static_cast<std::size_t>(channels);
    std::vector<T> out(px * n);
    for (std::size_t i = 0; i < px; ++i)
        for (int c = 0; c < channels; ++c) {
            bool invert = false;
            const double v = channel_value(s, map, i, c, invert);
            const auto q = static_cast<T>(std::lround(clamp01(v) * top));
            out[i * n + static_cast<std::size_t>(c)] = invert ? static_cast<T>(static_cast<T>(top) - q) : q;
        }
    return out;
}

std::vector<std::uint8_t> encode_one(const render::TextureSet& s, const MapKind& kind, int bits) {
    const int w = s.width, h = s.height_px;
    if (kind.channels == 1) {
        GrayImage img;
        img.width = w;
        img.height = h;
        img.pixels.resize(s.pixels());
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
            bool invert = false;
            img.pixels[i] = static_cast<float>(channel_value(s, kind.name, i, 0, invert));
        }
        return encode_png_gray(img, bits);
    }
    if (bits == 16) return encode_png_rgb16(w, h, kind.channels, samples<std::uint16_t>(s, kind.name, kind.channels));
    return encode_png_rgb8(w, h, kind.channels, samples<std::uint8_t>(s, kind.name, kind.channels));
}

/// No map holds a number that is not finite (docs/reliability.md): a NaN would become an
/// arbitrary pixel in a PNG (lround of NaN) and a NaN in the EXR. One is the bake's numeric
/// failure (exit 3), named by channel and pixel, before anything is encoded.
void check_finite(const render::TextureSet& s) {
    const std::pair<const char*, const std::vector<float>*> channels[] = {{"height", &s.height},
                                                                          {"normal", &s.normal},
                                                                          {"ambient occlusion", &s.ao},
                                                                          {"roughness", &s.roughness},
                                                                          {"crack mask", &s.mask}};
    for (const auto& [name, values] : channels) {
        const auto bad = std::find_if(values->begin(), values->end(), [](float v) { return !std::isfinite(v); });
        if (bad == values->end()) continue;
        const std::size_t per_pixel = std::max<std::size_t>(1, values->size() / std::max<std::size_t>(1, s.pixels()));
        const std::size_t i = static_cast<std::size_t>(bad - values->begin()) / per_pixel;
        const std::size_t w = static_cast<std::size_t>(std::max(1, s.width));
        throw NumericError("the baked " + std::string(name) + " holds "
                           + std::string(std::isnan(*bad) ? "NaN"
                                         : *bad > 0       ? "+inf"
                                                          : "-inf")
                           + " at pixel (" + std::to_string(i % w) + ", " + std::to_string(i / w) + ") of "
                           + std::to_string(s.width) + "×" + std::to_string(s.height_px) + "; no map was written");
    }
}

std::string names_text() {
    std::string t;
    for (const MapKind& k : KINDS)
        t += (t.empty() ? "" : ", ") + std::string(k.name);
    return t;
}

} // namespace

const std::vector<std::string>& map_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const MapKind& k : KINDS)
            v.emplace_back(k.name);
        return v;
    }();
    return names;
}

const std::string& default_maps() {
    static const std::string maps = "Color,NormalGL,NormalDX,Displacement,AmbientOcclusion,Roughness,Mask,ID";
    return maps;
}

const std::string& default_bit_depths() {
    static const std::string depths = "Displacement=16";
    return depths;
}

std::vector<MapRequest> parse_map_requests(const std::string& maps, const std::string& bit_depths,
                                           const std::string& where_maps, const std::string& where_bits) {
    std::vector<MapRequest> out;
    for (const std::string& raw : split(maps, ',')) {
        const std::string name = trim(raw);
        const MapKind* kind = find_kind(name);
        if (!kind)
            throw InputError(where_maps, "no map called '" + name + "'" + did_you_mean(name, map_names()),
                             "choose from " + names_text() + ", separated by commas");
        if (std::any_of(out.begin(), out.end(), [&](const MapRequest& m) { return m.name == name; }))
            throw InputError(where_maps, "'" + name + "' is listed twice", "name each map once");
        out.push_back({name, kind->default_bits});
    }
    if (out.empty()) throw InputError(where_maps, "no maps chosen", "name at least one map, e.g. Color,NormalGL");
    for (const std::string& raw : split(bit_depths, ',')) {
        const std::string item = trim(raw);
        if (item.empty()) continue;
        const auto eq = item.find('=');
        const std::string name = trim(item.substr(0, eq)),
                          bits = eq == std::string::npos ? "" : trim(item.substr(eq + 1));
        const MapKind* kind = find_kind(name);
        if (!kind)
            throw InputError(where_bits, "no map called '" + name + "'",
                             "write MAP=8 or MAP=16 with MAP one of " + names_text());
        if (bits != "8" && bits != "16")
            throw InputError(where_bits, "'" + item + "' is not MAP=8 or MAP=16", "give 8 or 16 bits per channel");
        if (bits == "16" && !kind->may_be_16bit)
            throw InputError(where_bits, name + " cannot be 16-bit",
                             name
                                 + " holds 8-bit sRGB colours; give 16 bits to data maps (normals, displacement, "
                                   "occlusion, roughness, mask, ORM)");
        for (MapRequest& m : out)
            if (m.name == name) m.bits = std::stoi(bits);
    }
    return out;
}

std::vector<EncodedMap> encode_maps(const render::TextureSet& s, const std::vector<MapRequest>& maps, bool exr,
                                    double* seconds) {
    Timer timer;
    check_finite(s);
    // Each map on its own thread: zlib is the bottleneck and the maps are independent.
    std::vector<std::future<std::vector<std::uint8_t>>> futures;
    for (const MapRequest& m : maps) {
        const MapKind* kind = find_kind(m.name);
        CRACKLE_ASSERT(kind, "unknown map " << m.name);
        futures.push_back(
            std::async(std::launch::async, [&s, kind, bits = m.bits] { return encode_one(s, *kind, bits); }));
    }
    std::vector<EncodedMap> out;
    for (std::size_t k = 0; k < maps.size(); ++k)
        out.push_back({maps[k].name, "png", futures[k].get()});
    if (exr) out.push_back({"Displacement", "exr", encode_exr_gray(s.height, s.width, s.height_px)});
    if (seconds) *seconds = timer.seconds();
    return out;
}

} // namespace crackle::io
