// OpenEXR in its own translation unit (its headers are heavy).
#include "core/error.hpp"
#include "io/texture_set.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStdIO.h>
#include <sstream>

namespace crackle::io {

std::vector<std::uint8_t> encode_exr_gray(const std::vector<float>& pixels, int width, int height) {
    Imf::Header header(width, height);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::StdOSStream stream;
    {
        // The file writes its offset table when it closes: take the bytes after that.
        Imf::OutputFile file(stream, header);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(pixels.data())), sizeof(float),
                                  sizeof(float) * static_cast<std::size_t>(width)));
        file.setFrameBuffer(fb);
        file.writePixels(height);
    }
    const std::string s = stream.str();
    return std::vector<std::uint8_t>(s.begin(), s.end());
}

std::vector<float> decode_exr_gray(const std::vector<std::uint8_t>& bytes, int& size, int* rows) {
    Imf::StdISStream stream;
    stream.str(std::string(bytes.begin(), bytes.end()));
    Imf::InputFile file(stream);
    const Imath::Box2i dw = file.header().dataWindow();
    size = dw.max.x - dw.min.x + 1;
    const int height = dw.max.y - dw.min.y + 1;
    if (rows) *rows = height;
    std::vector<float> pixels(static_cast<std::size_t>(size) * static_cast<std::size_t>(height));
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(pixels.data()), sizeof(float),
                              sizeof(float) * static_cast<std::size_t>(size)));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return pixels;
}

} // namespace crackle::io
