#include "render/offscreen_target.h"

#include <cstdio>
#include <string>

#include "core/error.h"

namespace deixis::render {

OffscreenTarget::OffscreenTarget(int width, int height) : width_(width), height_(height) {
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (width <= 0 || height <= 0 || width > max_size || height > max_size) {
    throw Error("offscreen target: size " + std::to_string(width) + " x " + std::to_string(height) +
                " is not within 1 x 1 to " + std::to_string(max_size) + " x " +
                std::to_string(max_size));
  }
  colour_ = create_texture(GL_TEXTURE_2D);
  glTextureStorage2D(colour_.get(), 1, GL_RGBA8, width, height);
  glTextureParameteri(colour_.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(colour_.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  depth_ = create_renderbuffer();
  glNamedRenderbufferStorage(depth_.get(), GL_DEPTH_COMPONENT24, width, height);
  framebuffer_ = create_framebuffer();
  glNamedFramebufferTexture(framebuffer_.get(), GL_COLOR_ATTACHMENT0, colour_.get(), 0);
  glNamedFramebufferRenderbuffer(framebuffer_.get(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                 depth_.get());
  const GLenum status = glCheckNamedFramebufferStatus(framebuffer_.get(), GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", status);
    throw Error(std::string("offscreen target: framebuffer incomplete (status ") + code + ")");
  }
  check_gl("offscreen target");
}

}  // namespace deixis::render
