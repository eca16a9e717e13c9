#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/png.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

using namespace crackle;

TEST_SUITE("io") {
    TEST_CASE("png: 16-bit grayscale round trip within 1/65535 and 8-bit within 1/255") {
        GrayImage img;
        img.width = 37;
        img.height = 11;
        for (int i = 0; i < img.width * img.height; ++i)
            img.pixels.push_back(static_cast<float>((i * 7919 % 1000) / 999.0));
        const GrayImage back16 = io::decode_png_gray16(io::encode_png_gray(img, 16));
        REQUIRE(back16.width == img.width);
        REQUIRE(back16.height == img.height);
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            CHECK(std::abs(back16.pixels[i] - img.pixels[i]) <= 0.5 / 65535 + 1e-7);

        const auto dir = test::scratch_dir("png");
        write_file_atomically(dir / "g8.png",
                              std::string_view(reinterpret_cast<const char*>(io::encode_png_gray(img, 8).data()),
                                               io::encode_png_gray(img, 8).size()));
        const GrayImage back8 = io::read_png_gray(dir / "g8.png");
        for (std::size_t i = 0; i < img.pixels.size(); ++i)
            CHECK(std::abs(back8.pixels[i] - img.pixels[i]) <= 0.5 / 255 + 1e-6);
    }

    TEST_CASE("png: a missing or broken file is an input error naming the file") {
        CHECK_THROWS_AS(io::read_png_gray("/no/such/file.png"), InputError);
        const auto dir = test::scratch_dir("png-bad");
        test::write_text(dir / "fake.png", "this is not a png");
        try {
            io::read_png_gray(dir / "fake.png");
            FAIL("expected an error");
        } catch (const InputError& e) {
            CHECK(std::string(e.what()).find("fake.png") != std::string::npos);
        }
    }
}
