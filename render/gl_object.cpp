#include "render/gl_object.h"

namespace deixis::render {

GlBuffer create_buffer() {
  GLuint name = 0;
  glCreateBuffers(1, &name);
  return GlBuffer(name);
}

GlVertexArray create_vertex_array() {
  GLuint name = 0;
  glCreateVertexArrays(1, &name);
  return GlVertexArray(name);
}

GlTexture create_texture(GLenum target) {
  GLuint name = 0;
  glCreateTextures(target, 1, &name);
  return GlTexture(name);
}

GlRenderbuffer create_renderbuffer() {
  GLuint name = 0;
  glCreateRenderbuffers(1, &name);
  return GlRenderbuffer(name);
}

GlFramebuffer create_framebuffer() {
  GLuint name = 0;
  glCreateFramebuffers(1, &name);
  return GlFramebuffer(name);
}

}  // namespace deixis::render
