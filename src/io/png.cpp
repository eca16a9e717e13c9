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

struct WriteState {
    std::vector<std::uint8_t>* out;
};

void write_bytes(png_structp png, png_bytep data, png_size_t length) {
    auto* state = static_cast<WriteState*>(png_get_io_ptr(png));
    state->out->insert(state->out->end(), data, data + length);
}

void flush_nothing(png_structp) {}

/// libpng's full API, for the compression level and filter the simplified API does not offer.
/// libpng reports errors by longjmp: nothing with a destructor lives inside the jump region;
/// `out`, `rows` and the error flag are set up before setjmp.
bool encode_rows(std::vector<std::uint8_t>& out, const std::vector<png_bytep>& rows, int width, int height,
                 int color_type, int bit_depth, int level) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    WriteState state{&out};
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &state, write_bytes, flush_nothing);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, color_type,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, level);
    // One filter for every row: Paeth compresses textures well and skips the adaptive search.
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_PAETH);
    png_write_info(png, info);
    if (bit_depth == 16) png_set_swap(png); // our samples are little-endian in memory
    png_write_image(png, const_cast<png_bytepp>(rows.data()));
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

std::vector<std::uint8_t> encode_raw(const void* pixels, int width, int height, int channels, int bit_depth) {
    const int color_type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                           : channels == 3 ? PNG_COLOR_TYPE_RGB
                                           : PNG_COLOR_TYPE_RGBA;
    const std::size_t row_bytes =
        static_cast<std::size_t>(width) * static_cast<std::size_t>(channels) * static_cast<std::size_t>(bit_depth / 8);
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    auto* base = static_cast<png_bytep>(const_cast<void*>(pixels));
    for (std::size_t y = 0; y < rows.size(); ++y)
        rows[y] = base + y * row_bytes;
    std::vector<std::uint8_t> out;
    out.reserve(row_bytes * rows.size() / 2);
    // zlib level 3 with the Paeth filter. On the 8 maps of a 4096² mud bake (2 threads): level 6
    // 3.15 s / 15.3 MB, level 3 2.0 s / 18.5 MB, level 1 1.8 s / 20.1 MB (docs/benchmarks.md).
    if (!encode_rows(out, rows, width, height, color_type, bit_depth, 3))
        throw NumericError("PNG encoding failed (" + std::to_string(width) + " x " + std::to_string(height) + ")");
    return out;
}

} // namespace

std::vector<std::uint8_t> encode_png_gray(const GrayImage& image, int bits) {
    CRACKLE_ASSERT(bits == 8 || bits == 16, "PNG bit depth must be 8 or 16");
    if (bits == 8) {
        std::vector<std::uint8_t> px(image.pixels.size());
        for (std::size_t i = 0; i < px.size(); ++i)
            px[i] = static_cast<std::uint8_t>(std::lround(clamp01(image.pixels[i]) * 255.0));
        return encode_raw(px.data(), image.width, image.height, 1, 8);
    }
    // 16-bit values as they are (no gamma chunk: displacement is data, not colour).
    std::vector<std::uint16_t> px(image.pixels.size());
    for (std::size_t i = 0; i < px.size(); ++i)
        px[i] = static_cast<std::uint16_t>(std::lround(clamp01(image.pixels[i]) * 65535.0));
    return encode_raw(px.data(), image.width, image.height, 1, 16);
}

namespace {
/// RGB(A) samples of any depth, checked against the image size.
template <class Sample>
std::vector<std::uint8_t> encode_rgb(int width, int height, int channels, const std::vector<Sample>& samples) {
    CRACKLE_ASSERT(channels == 3 || channels == 4, "RGB PNG needs 3 or 4 channels");
    CRACKLE_ASSERT(samples.size()
                       == static_cast<std::size_t>(width) * static_cast<std::size_t>(height)
                              * static_cast<std::size_t>(channels),
                   "sample buffer size does not match the image size");
    return encode_raw(samples.data(), width, height, channels, 8 * static_cast<int>(sizeof(Sample)));
}
} // namespace

std::vector<std::uint8_t> encode_png_rgb8(int width, int height, int channels,
                                          const std::vector<std::uint8_t>& pixels) {
    return encode_rgb(width, height, channels, pixels);
}

std::vector<std::uint8_t> encode_png_rgb16(int width, int height, int channels,
                                           const std::vector<std::uint16_t>& samples) {
    return encode_rgb(width, height, channels, samples);
}

std::vector<std::uint8_t> decode_png_rgb8(const std::vector<std::uint8_t>& bytes, int& width, int& height) {
    png_image img;
    std::memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
        throw InputError("", std::string("not a readable PNG: ") + img.message, "check the file");
    img.format = PNG_FORMAT_RGB;
    std::vector<std::uint8_t> out(PNG_IMAGE_SIZE(img));
    if (!png_image_finish_read(&img, nullptr, out.data(), 0, nullptr)) {
        png_image_free(&img);
        throw InputError("", std::string("PNG decoding failed: ") + img.message, "check the file");
    }
    width = static_cast<int>(img.width);
    height = static_cast<int>(img.height);
    return out;
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
