#pragma once
/// @file PNG input and output (libpng's simplified API, which reports errors by return value
/// rather than longjmp).

#include "core/image.hpp"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace crackle::io {

/// Reads any PNG as grayscale in [0, 1] (8-bit value / 255; colour converts to luminance).
/// Throws InputError naming the file when it is missing or not a PNG.
GrayImage read_png_gray(const std::filesystem::path& path);

/// Encodes a grayscale image as an 8-bit or 16-bit PNG (values clamped to [0, 1]).
std::vector<std::uint8_t> encode_png_gray(const GrayImage& image, int bits);

/// Encodes interleaved 8-bit RGB or RGBA pixels (row 0 at the top).
std::vector<std::uint8_t> encode_png_rgb8(int width, int height, int channels, const std::vector<std::uint8_t>& pixels);

/// Encodes interleaved 16-bit RGB or RGBA samples (data maps: no gamma chunk).
std::vector<std::uint8_t> encode_png_rgb16(int width, int height, int channels,
                                           const std::vector<std::uint16_t>& samples);

/// Decodes a PNG from memory into interleaved 8-bit RGB (for tests and golden images).
std::vector<std::uint8_t> decode_png_rgb8(const std::vector<std::uint8_t>& bytes, int& width, int& height);

/// Decodes a PNG from memory into 16-bit-precision grayscale in [0, 1] (for round-trip tests).
GrayImage decode_png_gray16(const std::vector<std::uint8_t>& bytes);

} // namespace crackle::io
