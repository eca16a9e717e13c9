/// The fuzz corpus replayed (issue 16): every input the fuzzers keep in tests/fuzz/corpus/, every
/// crash they found (a regression input there), and every shipped preset, through the same
/// targets as scripts/fuzz, built with g++ and without libFuzzer. A target may refuse an input
/// only with an InputError, which it catches; anything else fails here.
#include "fuzz/fuzz_targets.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> files_under(const fs::path& dir, const std::string& extension = "") {
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && (extension.empty() || e.path().extension() == extension)) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

std::string bytes_of(const fs::path& file) {
    std::ifstream is(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(is), std::istreambuf_iterator<char>()};
}

template <class Target> void replay(const std::vector<fs::path>& files, Target target) {
    for (const fs::path& f : files) {
        CAPTURE(f.string());
        const std::string b = bytes_of(f);
        CHECK_NOTHROW(target(reinterpret_cast<const std::uint8_t*>(b.data()), b.size()));
    }
}

} // namespace

TEST_SUITE("io") {
    TEST_CASE("fuzz corpus: the preset target takes every corpus input and every shipped preset") {
        const fs::path root = CRACKLE_SOURCE_DIR;
        const auto corpus = files_under(root / "tests/fuzz/corpus/preset");
        const auto presets = files_under(root / "presets", ".toml");
        CHECK(corpus.size() >= 5);
        CHECK(presets.size() >= 20);
        replay(corpus, crackle::fuzz::preset);
        replay(presets, crackle::fuzz::preset);
    }

    TEST_CASE("fuzz corpus: the pattern target takes every corpus input, and damaged copies of each") {
        const auto corpus = files_under(fs::path(CRACKLE_SOURCE_DIR) / "tests/fuzz/corpus/pattern");
        CHECK(corpus.size() >= 2);
        replay(corpus, crackle::fuzz::pattern);
        // Truncations and flipped bytes at fixed places (with a valid checksum, so the decoder's
        // own checks must catch them).
        for (const fs::path& f : corpus) {
            const std::string b = bytes_of(f);
            for (std::size_t cut : {std::size_t{0}, std::size_t{9}, b.size() / 3, b.size() / 2, b.size() - 1}) {
                CAPTURE(cut);
                CHECK_NOTHROW(crackle::fuzz::pattern(reinterpret_cast<const std::uint8_t*>(b.data()), cut));
            }
            for (std::size_t at = 8; at < b.size(); at += b.size() / 97 + 1) {
                std::string damaged = b;
                damaged[at] = static_cast<char>(damaged[at] ^ 0x5a);
                CAPTURE(at);
                CHECK_NOTHROW(
                    crackle::fuzz::pattern(reinterpret_cast<const std::uint8_t*>(damaged.data()), damaged.size()));
            }
        }
    }
}
