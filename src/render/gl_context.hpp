#pragma once
/// @file The off-screen OpenGL context (OSMesa, GL 3.3+ core on llvmpipe). Context creation
/// lives in this one file so an EGL "surfaceless" sibling can replace it where Mesa has
/// dropped OSMesa (style guide §1). `GALLIUM_DRIVER` is left to the user.

#include <memory>
#include <string>

namespace crackle::render {

class GlContext {
public:
    /// Creates and makes current a core-profile context. Throws InputError naming the
    /// package to install when none can be made.
    GlContext();
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    /// "4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string description() const;
    int max_samples() const { return m_max_samples; }
    int max_texture_size() const { return m_max_texture_size; }

private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
    int m_max_samples = 1;
    int m_max_texture_size = 0;
};

} // namespace crackle::render
