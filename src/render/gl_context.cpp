#include "render/gl_context.hpp"

#include "core/error.hpp"
#include "render/gl.hpp"

#include <vector>

namespace crackle::render {

struct GlContext::Impl {
    OSMesaContext context = nullptr;
    std::vector<unsigned char> dummy; // OSMesa needs a default buffer; we render into FBOs
};

GlContext::GlContext() : m_impl(std::make_unique<Impl>()) {
    const int attribs[] = {OSMESA_FORMAT,
                           OSMESA_RGBA,
                           OSMESA_DEPTH_BITS,
                           24,
                           OSMESA_PROFILE,
                           OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION,
                           3,
                           OSMESA_CONTEXT_MINOR_VERSION,
                           3,
                           0};
    m_impl->context = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!m_impl->context)
        throw InputError("OpenGL", "cannot create an OSMesa OpenGL 3.3 core context",
                         "install Mesa's off-screen renderer: scripts/setup (apt-get install libosmesa6)");
    m_impl->dummy.assign(4 * 4 * 4, 0);
    if (!OSMesaMakeCurrent(m_impl->context, m_impl->dummy.data(), GL_UNSIGNED_BYTE, 4, 4)) {
        OSMesaDestroyContext(m_impl->context);
        throw InputError("OpenGL", "cannot make the OSMesa context current", "check the Mesa installation");
    }
    glGetIntegerv(GL_MAX_SAMPLES, &m_max_samples);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &m_max_texture_size);
}

GlContext::~GlContext() {
    if (m_impl && m_impl->context) OSMesaDestroyContext(m_impl->context);
}

std::string GlContext::description() const {
    auto str = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return s ? std::string(s) : std::string("?");
    };
    return str(GL_VERSION) + ", " + str(GL_RENDERER);
}

} // namespace crackle::render
