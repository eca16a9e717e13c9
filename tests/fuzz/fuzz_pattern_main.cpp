/// libFuzzer entry for the pattern-file loader (scripts/fuzz pattern).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return crackle::fuzz::pattern(data, size);
}
