#include "render/gl_program.hpp"

#include "core/atomic_file.hpp"
#include "core/embedded.hpp"
#include "core/error.hpp"
#include "render/gl.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

namespace crackle::render {

std::string shader_source(const std::string& name, const std::string& shader_dir) {
    if (!shader_dir.empty()) return read_file(std::filesystem::path(shader_dir) / name, "shader");
    for (const EmbeddedFile& f : embedded::shaders())
        if (f.path == name) return std::string(f.text);
    CRACKLE_ASSERT(false, "no embedded shader '" << name << "'");
    return {};
}

std::string numbered(std::string_view source) {
    std::ostringstream os;
    std::istringstream is{std::string(source)};
    std::string line;
    for (int n = 1; std::getline(is, line); ++n)
        os << (n < 10 ? "   " : n < 100 ? "  " : " ") << n << " | " << line << "\n";
    return os.str();
}

namespace {

/// A user's shader that does not compile: "<dir>/<file>:<line>: <the compiler's first error>".
/// The source strings are numbered by #line: 0 is common.glsl, 1 the shader's own file
/// (Mesa's log reads "1:33(1): error: ...").
[[noreturn]] void refuse_user_shader(const std::string& log, const std::string& shader_dir, const std::string& file) {
    std::istringstream is(log);
    std::string line, first;
    while (std::getline(is, line))
        if (line.find("error") != std::string::npos) {
            first = line;
            break;
        }
    if (first.empty()) first = log.substr(0, log.find('\n'));
    int string_number = 1, line_number = 0, used = 0;
    std::string where = (std::filesystem::path(shader_dir) / file).string();
    if (std::sscanf(first.c_str(), "%d:%d(%*d): %n", &string_number, &line_number, &used) >= 2 && used > 0) {
        if (string_number == 0) where = (std::filesystem::path(shader_dir) / "common.glsl").string();
        where += ":" + std::to_string(line_number);
        first = first.substr(static_cast<std::size_t>(used));
    }
    throw InputError(where, "GLSL does not compile: " + first,
                     "fix the shader, or leave out --shader-dir to use the built-in shaders");
}

unsigned compile(const std::string& program, GLenum type, const std::string& body, const std::string& shader_dir,
                 const std::string& file) {
    const std::string source =
        "#version 330 core\n#line 1 0\n" + shader_source("common.glsl", shader_dir) + "\n#line 1 1\n" + body;
    const GLuint shader = glCreateShader(type);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)));
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        if (!shader_dir.empty()) refuse_user_shader(log.data(), shader_dir, file);
        throw NumericError("shader '" + program + "' (" + (type == GL_VERTEX_SHADER ? "vertex" : "fragment")
                           + ") failed to compile:\n" + std::string(log.data())
                           + "\nsource (line numbers as in the log):\n" + numbered(source));
    }
    return shader;
}
} // namespace

GlProgram::GlProgram(const std::string& name, const std::string& vertex, const std::string& fragment,
                     const std::string& shader_dir, const std::array<std::string, 2>& files)
    : m_name(name) {
    const unsigned vs = compile(name, GL_VERTEX_SHADER, vertex, shader_dir, files[0]);
    const unsigned fs = compile(name, GL_FRAGMENT_SHADER, fragment, shader_dir, files[1]);
    m_program = glCreateProgram();
    glAttachShader(m_program, vs);
    glAttachShader(m_program, fs);
    glLinkProgram(m_program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(m_program, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(m_program, GL_INFO_LOG_LENGTH, &length);
        std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)));
        glGetProgramInfoLog(m_program, length, nullptr, log.data());
        glDeleteProgram(m_program);
        if (!shader_dir.empty())
            throw InputError(shader_dir + " (" + files[0] + ", " + files[1] + ")",
                             "the shaders do not link: " + std::string(log.data()),
                             "make the vertex shader's outputs match the fragment shader's inputs, or leave out "
                             "--shader-dir");
        throw NumericError("shader program '" + name + "' failed to link:\n" + std::string(log.data()));
    }
}

GlProgram::~GlProgram() {
    if (m_program) glDeleteProgram(m_program);
}

void GlProgram::use() const {
    glUseProgram(m_program);
}

int GlProgram::uniform(const char* name) const {
    const GLint loc = glGetUniformLocation(m_program, name);
    CRACKLE_ASSERT(loc >= 0, "shader program '" << m_name << "' has no active uniform '" << name << "'");
    return loc;
}

void GlProgram::set(const char* name, float v) const {
    glUniform1f(uniform(name), v);
}
void GlProgram::set(const char* name, unsigned v) const {
    glUniform1ui(uniform(name), v);
}
void GlProgram::set(const char* name, int v) const {
    glUniform1i(uniform(name), v);
}
void GlProgram::set(const char* name, const Vec2& v) const {
    glUniform2f(uniform(name), static_cast<float>(v.x()), static_cast<float>(v.y()));
}
void GlProgram::set(const char* name, const Vec3& v) const {
    glUniform3f(uniform(name), static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}
void GlProgram::set(const char* name, const Eigen::Vector4d& v) const {
    glUniform4f(uniform(name), static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]),
                static_cast<float>(v[3]));
}

} // namespace crackle::render
