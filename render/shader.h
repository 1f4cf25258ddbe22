#pragma once
// A linked GLSL program. Sources carry no #version line: the program prepends "#version 450
// core", the caller's #defines and a #line 1, so the compiler's line numbers are the file's own.
// A compile or link failure throws deixis::Error with the stage's name and the driver's log.

#include <span>
#include <string>
#include <string_view>

#include "render/gl.h"

namespace deixis::render {

struct ShaderStage {
  GLenum type = GL_VERTEX_SHADER;  // or GL_FRAGMENT_SHADER, ...
  std::string_view name;           // for messages, e.g. "mesh.vert"
  std::string_view source;         // GLSL without #version
};

class ShaderProgram {
 public:
  // `defines` is inserted after #version verbatim, e.g. "#define SKINNED 1\n".
  ShaderProgram(std::span<const ShaderStage> stages, std::string_view defines = {});
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  GLuint id() const { return program_; }
  // A uniform's location; −1 (ignored by glProgramUniform*) when the compiler removed it.
  GLint uniform(const char* name) const { return glGetUniformLocation(program_, name); }

 private:
  GLuint program_ = 0;
};

}  // namespace deixis::render
