#include "render/gl_target.hpp"

#include "core/error.hpp"

#include <string>

namespace crackle::render {

namespace {

GLuint make_texture(GLenum internal, int size, int samples) {
    GLuint t = 0;
    glGenTextures(1, &t);
    if (samples > 1) {
        glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, t);
        glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, samples, internal, size, size, GL_TRUE);
    } else {
        glBindTexture(GL_TEXTURE_2D, t);
        glTexStorage2D(GL_TEXTURE_2D, 1, internal, size, size);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    return t;
}

} // namespace

GlTarget::GlTarget(const std::vector<GLenum>& formats, int size, int samples_, bool with_depth) : samples(samples_) {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    std::vector<GLenum> buffers;
    for (std::size_t i = 0; i < formats.size(); ++i) {
        const GLuint t = make_texture(formats[i], size, samples);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i),
                               samples > 1 ? GL_TEXTURE_2D_MULTISAMPLE : GL_TEXTURE_2D, t, 0);
        color.push_back(t);
        buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
    }
    if (with_depth) {
        glGenRenderbuffers(1, &depth);
        glBindRenderbuffer(GL_RENDERBUFFER, depth);
        if (samples > 1)
            glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, size, size);
        else
            glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, size, size);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    }
    glDrawBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw NumericError("off-screen framebuffer incomplete (status 0x" + std::to_string(status) + ")");
}

GlTarget::~GlTarget() {
    glDeleteFramebuffers(1, &fbo);
    if (depth) glDeleteRenderbuffers(1, &depth);
    glDeleteTextures(static_cast<GLsizei>(color.size()), color.data());
}

} // namespace crackle::render
