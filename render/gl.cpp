#include "render/gl.h"

#include "core/error.h"

namespace deixis::render {

std::string_view gl_error_name(GLenum error) {
  switch (error) {
    case GL_NO_ERROR:
      return "GL_NO_ERROR";
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
      return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
      return "GL_STACK_OVERFLOW";
    default:
      return "unknown GL error";
  }
}

void check_gl(std::string_view where) {
  std::string errors;
  // glGetError returns one flag per call; a context without errors returns GL_NO_ERROR at once.
  // The bound keeps a lost context (which may report errors forever) from looping.
  for (int i = 0; i < 16; ++i) {
    const GLenum error = glGetError();
    if (error == GL_NO_ERROR) {
      break;
    }
    errors += (errors.empty() ? "" : ", ") + std::string(gl_error_name(error));
  }
  if (!errors.empty()) {
    throw Error(std::string(where) + ": OpenGL error " + errors);
  }
}

std::string gl_description() {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer != nullptr ? renderer : "unknown renderer") + ", " +
         (version != nullptr ? version : "unknown version");
}

void require_gl_version(int major, int minor, std::string_view who) {
  GLint found_major = 0;
  GLint found_minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &found_major);
  glGetIntegerv(GL_MINOR_VERSION, &found_minor);
  if (found_major < major || (found_major == major && found_minor < minor)) {
    throw Error(std::string(who) + ": needs OpenGL " + std::to_string(major) + "." +
                std::to_string(minor) + " core, the current context is " + gl_description());
  }
}

}  // namespace deixis::render
