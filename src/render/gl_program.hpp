#pragma once
/// @file GLSL programs: compile with the shared helpers, report errors with numbered source
/// lines (polyscope: gl_engine.cpp), and refuse uniforms that do not exist.

#include "core/math.hpp"

#include <array>
#include <string>
#include <string_view>

namespace crackle::render {

/// The text of an embedded shader (shaders/<name>), or the file in `shader_dir` when given
/// (for editing shaders without rebuilding).
std::string shader_source(const std::string& name, const std::string& shader_dir = "");

class GlProgram {
public:
    /// Compiles `vertex` and `fragment` (without #version; common.glsl is prepended) and links.
    /// A built-in shader that fails throws NumericError with the info log and the numbered
    /// source; a user's shader (from `shader_dir`) throws InputError naming its file and line
    /// (`files`: the vertex and fragment file names in that folder).
    GlProgram(const std::string& name, const std::string& vertex, const std::string& fragment,
              const std::string& shader_dir = "", const std::array<std::string, 2>& files = {});
    ~GlProgram();
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;

    void use() const;
    /// Location of a uniform that must exist (CRACKLE_ASSERT otherwise).
    int uniform(const char* name) const;
    void set(const char* name, float v) const;
    void set(const char* name, unsigned v) const;
    void set(const char* name, int v) const;
    void set(const char* name, const Vec2& v) const;
    void set(const char* name, const Vec3& v) const;
    void set(const char* name, const Eigen::Vector4d& v) const;
    unsigned id() const { return m_program; }

private:
    std::string m_name;
    unsigned m_program = 0;
};

/// "  1 | #version 330 core\n  2 | ..." for error messages.
std::string numbered(std::string_view source);

} // namespace crackle::render
