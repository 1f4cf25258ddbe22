#pragma once
// Ownership of one OpenGL object name (buffer, vertex array, texture, framebuffer): deleted with
// its matching glDelete* when the owner goes, moved but never copied. Destroy owners while their
// context is current.

#include <utility>

#include "render/gl.h"

namespace deixis::render {

template <void (*Delete)(GLsizei, const GLuint*)>
class GlObject {
 public:
  GlObject() = default;
  explicit GlObject(GLuint name) : name_(name) {}
  ~GlObject() { reset(); }
  GlObject(GlObject&& other) noexcept : name_(std::exchange(other.name_, 0)) {}
  GlObject& operator=(GlObject&& other) noexcept {
    if (this != &other) {
      reset();
      name_ = std::exchange(other.name_, 0);
    }
    return *this;
  }
  GlObject(const GlObject&) = delete;
  GlObject& operator=(const GlObject&) = delete;

  GLuint get() const { return name_; }
  void reset() {
    if (name_ != 0) {
      Delete(1, &name_);
      name_ = 0;
    }
  }

 private:
  GLuint name_ = 0;
};

using GlBuffer = GlObject<glDeleteBuffers>;
using GlVertexArray = GlObject<glDeleteVertexArrays>;
using GlTexture = GlObject<glDeleteTextures>;
using GlRenderbuffer = GlObject<glDeleteRenderbuffers>;
using GlFramebuffer = GlObject<glDeleteFramebuffers>;

// Each creates one object with the 4.5 direct-state-access glCreate* (named and initialised).
GlBuffer create_buffer();
GlVertexArray create_vertex_array();
GlTexture create_texture(GLenum target);
GlRenderbuffer create_renderbuffer();
GlFramebuffer create_framebuffer();

}  // namespace deixis::render
