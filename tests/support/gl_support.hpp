#pragma once
/// @file An OpenGL context for render tests: skipped when none can be made, unless
/// CRACKLE_REQUIRE_GL=1 (as in CI), where a missing context is a failure.

#include "core/error.hpp"
#include "render/gl_context.hpp"

#include <doctest/doctest.h>

#include <cstdlib>
#include <memory>
#include <string>

namespace crackle::test {

inline std::unique_ptr<render::GlContext> gl_context_or_skip() {
    try {
        return std::make_unique<render::GlContext>();
    } catch (const InputError& e) {
        const char* require = std::getenv("CRACKLE_REQUIRE_GL");
        if (require && std::string(require) == "1") FAIL("no OpenGL context: " << e.what());
        MESSAGE("skipped: no OpenGL context (" << e.what() << ")");
        return nullptr;
    }
}

} // namespace crackle::test
