#include "io/png.hpp"

#include "core/atomic_file.hpp"
#include "core/error.hpp"

#include <png.h>

#include <cstring>

namespace crackle::io {

GrayImage read_png_gray(const std::filesystem::path& path) {
    const std::string bytes = read_file(path, "image file");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
        throw InputError(path.string(), std::string("not a readable PNG: ") + img.message,
                         "save the image as PNG (grayscale or colour)");
    img.format = PNG_FORMAT_GRAY;
    std::vector<std::uint8_t> buffer(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, nullptr, buffer.data(), 0, nullptr)) {
        png_image_free(&img);
        throw InputError(path.string(), std::string("PNG decoding failed: ") + img.message, "re-save the image");
    }
    GrayImage out;
    out.width = static_cast<int>(img.width);
    out.height = static_cast<int>(img.height);
    out.pixels.resize(buffer.size());
    for (std::size_t i = 0; i < buffer.size(); ++i)
        out.pixels[i] = static_cast<float>(buffer[i]) / 255.0f;
    return out;
}

namespace {
std::vector<std::uint8_t> encode(png_image& img, const void* data) {
    png_alloc_size_t size = 0;
    if (!png_image_write_get_memory_size(img, size, 0, data, 0, nullptr))
        throw NumericError(std::string("PNG encoding failed: ") + img.message);
    std::vector<std::uint8_t> out(size);
    if (!png_image_write_to_memory(&img, out.data(), &size, 0, data, 0, nullptr))
        throw NumericError(std::string("PNG encoding failed: ") + img.message);
    out.resize(size);
    return out;
}
} // namespace

std::vector<std::uint8_t> encode_png_gray(const GrayImage& image, int bits) {
    CRACKLE_ASSERT(bits == 8 || bits == 16, "PNG bit depth must be 8 or 16");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = static_cast<png_uint_32>(image.width);
    img.height = static_cast<png_uint_32>(image.height);
    if (bits == 8) {
        img.format = PNG_FORMAT_GRAY;
        std::vector<std::uint8_t> px(image.pixels.size());
        for (std::size_t i = 0; i < px.size(); ++i)
            px[i] = static_cast<std::uint8_t>(std::lround(clamp01(image.pixels[i]) * 255.0));
        return encode(img, px.data());
    }
    // 16-bit: PNG_FORMAT_LINEAR_Y stores the values as they are (gAMA 1.0), no sRGB curve.
    img.format = PNG_FORMAT_LINEAR_Y;
    std::vector<std::uint16_t> px(image.pixels.size());
    for (std::size_t i = 0; i < px.size(); ++i)
        px[i] = static_cast<std::uint16_t>(std::lround(clamp01(image.pixels[i]) * 65535.0));
    return encode(img, px.data());
}

std::vector<std::uint8_t> encode_png_rgb8(int width, int height, int channels,
                                          const std::vector<std::uint8_t>& pixels) {
    CRACKLE_ASSERT(channels == 3 || channels == 4, "RGB PNG needs 3 or 4 channels");
    CRACKLE_ASSERT(pixels.size()
                       == static_cast<std::size_t>(width) * static_cast<std::size_t>(height)
                              * static_cast<std::size_t>(channels),
                   "pixel buffer size does not match the image size");
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = static_cast<png_uint_32>(width);
    img.height = static_cast<png_uint_32>(height);
    img.format = channels == 3 ? PNG_FORMAT_RGB : PNG_FORMAT_RGBA;
    return encode(img, pixels.data());
}

GrayImage decode_png_gray16(const std::vector<std::uint8_t>& bytes) {
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
        throw InputError("", std::string("not a readable PNG: ") + img.message, "check the file");
    img.format = PNG_FORMAT_LINEAR_Y;
    std::vector<std::uint16_t> buffer(PNG_IMAGE_SIZE(img) / 2);
    if (!png_image_finish_read(&img, nullptr, buffer.data(), 0, nullptr)) {
        png_image_free(&img);
        throw InputError("", std::string("PNG decoding failed: ") + img.message, "check the file");
    }
    GrayImage out;
    out.width = static_cast<int>(img.width);
    out.height = static_cast<int>(img.height);
    out.pixels.resize(buffer.size());
    for (std::size_t i = 0; i < buffer.size(); ++i)
        out.pixels[i] = static_cast<float>(buffer[i] / 65535.0);
    return out;
}

} // namespace crackle::io
