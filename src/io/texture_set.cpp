#include "io/texture_set.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"
#include "io/png.hpp"

#include <future>

namespace crackle::io {

namespace {

std::vector<std::uint8_t> gray8(const std::vector<float>& v, int width, int height) {
    GrayImage img;
    img.width = width;
    img.height = height;
    img.pixels = v;
    return encode_png_gray(img, 8);
}

std::uint8_t unorm8(double x) {
    return static_cast<std::uint8_t>(std::lround(clamp01(x) * 255.0));
}

/// The PNG bytes of one map, by its suffix (ambientCG's names, or "ORM").
std::vector<std::uint8_t> encode_png(const render::TextureSet& s, const std::string& suffix) {
    const int w = s.width, h = s.height_px;
    const std::size_t px = s.pixels();
    if (suffix == "Color") return encode_png_rgb8(w, h, 3, s.color);
    if (suffix == "NormalGL" || suffix == "NormalDX") {
        // Normals: (n + 1) / 2; OpenGL convention has +Y (green) pointing up the image (+v),
        // DirectX's points down: the green channels are complements.
        const bool directx = suffix == "NormalDX";
        std::vector<std::uint8_t> rgb(3 * px);
        for (std::size_t i = 0; i < px; ++i) {
            rgb[3 * i] = unorm8(0.5 * s.normal[3 * i] + 0.5);
            const std::uint8_t g = unorm8(0.5 * s.normal[3 * i + 1] + 0.5);
            rgb[3 * i + 1] = directx ? static_cast<std::uint8_t>(255 - g) : g;
            rgb[3 * i + 2] = unorm8(0.5 * s.normal[3 * i + 2] + 0.5);
        }
        return encode_png_rgb8(w, h, 3, rgb);
    }
    if (suffix == "Displacement") {
        GrayImage disp;
        disp.width = w;
        disp.height = h;
        disp.pixels.resize(px);
        for (std::size_t i = 0; i < px; ++i)
            disp.pixels[i] = static_cast<float>(s.height[i] / s.height_scale);
        return encode_png_gray(disp, 16);
    }
    if (suffix == "AmbientOcclusion") return gray8(s.ao, w, h);
    if (suffix == "Roughness") return gray8(s.roughness, w, h);
    if (suffix == "Mask") return gray8(s.mask, w, h);
    if (suffix == "ID") return encode_png_rgb8(w, h, 3, s.id);
    CRACKLE_ASSERT(suffix == "ORM", "no PNG map is called " << suffix);
    // glTF's packed map: occlusion (R), roughness (G), metallic (B = 0).
    std::vector<std::uint8_t> orm(3 * px);
    for (std::size_t i = 0; i < px; ++i) {
        orm[3 * i] = unorm8(s.ao[i]);
        orm[3 * i + 1] = unorm8(s.roughness[i]);
        orm[3 * i + 2] = 0;
    }
    return encode_png_rgb8(w, h, 3, orm);
}

} // namespace

std::vector<EncodedMap> encode_texture_set(const render::TextureSet& s, bool exr, double* seconds) {
    Timer timer;
    // Each map is encoded on its own thread (zlib is the bottleneck; the maps are independent).
    const std::vector<std::string> suffixes = {"Color",     "NormalGL", "NormalDX", "Displacement", "AmbientOcclusion",
                                               "Roughness", "Mask",     "ID"};
    std::vector<std::future<std::vector<std::uint8_t>>> futures;
    for (const std::string& suffix : suffixes)
        futures.push_back(std::async(std::launch::async, [&s, &suffix] { return encode_png(s, suffix); }));
    std::vector<EncodedMap> maps;
    for (std::size_t k = 0; k < suffixes.size(); ++k)
        maps.push_back({suffixes[k], "png", futures[k].get()});
    if (exr) maps.push_back({"Displacement", "exr", encode_exr_gray(s.height, s.width, s.height_px)});
    if (seconds) *seconds = timer.seconds();
    return maps;
}

EncodedMap encode_map(const render::TextureSet& set, const std::string& suffix) {
    return {suffix, "png", encode_png(set, suffix)};
}

EncodedMap encode_orm(const render::TextureSet& set) {
    return encode_map(set, "ORM");
}

std::filesystem::path map_path(const std::filesystem::path& dir, const std::string& name, const EncodedMap& map) {
    return dir / (name + "_" + map.suffix + "." + map.extension);
}

} // namespace crackle::io
