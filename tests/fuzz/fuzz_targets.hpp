#pragma once
/// @file The fuzz targets (issue 16): one input in, every failure must be an InputError. Built
/// twice: as libFuzzer executables with clang (CRACKLE_FUZZ=ON, scripts/fuzz), and into the
/// test suite, which replays the corpus in tests/fuzz/corpus/ with g++ (test_fuzz_corpus.cpp).

#include <cstddef>
#include <cstdint>

namespace crackle::fuzz {

/// A preset and its `extends` parent and `--set` overrides, split at lines "--":
/// part 0 is main.toml, part 1 parent.toml beside it (extends = "parent" reaches it), part 2 one
/// override per line. Loads it with io::load_preset and, when it loads, builds its scene.
int preset(const std::uint8_t* data, std::size_t size);

/// A pattern file's bytes, with a valid checksum appended (so the fuzzer gets past it), through
/// fracture::decode_pattern.
int pattern(const std::uint8_t* data, std::size_t size);

} // namespace crackle::fuzz
