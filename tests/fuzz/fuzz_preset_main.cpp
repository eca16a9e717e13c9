/// libFuzzer entry for the preset parser and schema (scripts/fuzz preset).
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return crackle::fuzz::preset(data, size);
}
