#include "render/shader.h"

#include <utility>
#include <vector>

#include "core/error.h"

namespace deixis::render {
namespace {

std::string_view stage_kind(GLenum type) {
  switch (type) {
    case GL_VERTEX_SHADER:
      return "vertex";
    case GL_FRAGMENT_SHADER:
      return "fragment";
    case GL_GEOMETRY_SHADER:
      return "geometry";
    case GL_COMPUTE_SHADER:
      return "compute";
    default:
      return "unknown-stage";
  }
}

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
  return log;
}

std::string program_log(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
  return log;
}

GLuint compile(const ShaderStage& stage, std::string_view defines) {
  const std::string header = "#version 450 core\n" + std::string(defines) + "\n#line 1\n";
  const char* parts[] = {header.data(), stage.source.data()};
  const GLint lengths[] = {static_cast<GLint>(header.size()),
                           static_cast<GLint>(stage.source.size())};
  const GLuint shader = glCreateShader(stage.type);
  if (shader == 0) {
    throw Error("shader '" + std::string(stage.name) + "': glCreateShader failed (" +
                std::string(gl_error_name(glGetError())) + "; is a GL context current?)");
  }
  glShaderSource(shader, 2, parts, lengths);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw Error("shader '" + std::string(stage.name) + "' (" + std::string(stage_kind(stage.type)) +
                ") failed to compile:\n" + log);
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(std::span<const ShaderStage> stages, std::string_view defines) {
  std::vector<GLuint> shaders;
  try {
    for (const ShaderStage& stage : stages) {
      shaders.push_back(compile(stage, defines));
    }
  } catch (...) {
    for (const GLuint s : shaders) {
      glDeleteShader(s);
    }
    throw;
  }
  program_ = glCreateProgram();
  for (const GLuint s : shaders) {
    glAttachShader(program_, s);
  }
  glLinkProgram(program_);
  for (const GLuint s : shaders) {
    glDetachShader(program_, s);
    glDeleteShader(s);
  }
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    std::string names;
    for (const ShaderStage& stage : stages) {
      names += (names.empty() ? "" : " + ") + std::string(stage.name);
    }
    const std::string log = program_log(program_);
    glDeleteProgram(program_);
    program_ = 0;
    throw Error("shader program " + names + " failed to link:\n" + log);
  }
}

ShaderProgram::~ShaderProgram() {
  if (program_ != 0) {
    glDeleteProgram(program_);
  }
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : program_(std::exchange(other.program_, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (program_ != 0) {
      glDeleteProgram(program_);
    }
    program_ = std::exchange(other.program_, 0);
  }
  return *this;
}

}  // namespace deixis::render
