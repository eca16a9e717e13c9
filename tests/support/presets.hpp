#pragma once
/// @file Loading a preset with --set overrides in tests, and the message of one that fails.

#include "core/error.hpp"
#include "io/preset.hpp"

#include <string>
#include <vector>

namespace crackle::test {

inline io::Preset load(const std::string& name, std::vector<std::string> overrides = {}) {
    io::PresetRequest r;
    r.name_or_path = name;
    r.overrides = std::move(overrides);
    return io::load_preset(r);
}

/// The message of the InputError that loading throws ("" if none).
inline std::string load_error(const std::string& name, std::vector<std::string> overrides = {}) {
    try {
        load(name, std::move(overrides));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace crackle::test
