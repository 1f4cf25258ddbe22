// Shader programs: the embedded sources build, and a broken one is reported with the stage's name
// and the driver's log rather than crashing or drawing nothing.

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "render/headless_context.h"
#include "render/shader.h"
#include "render/shader_sources.h"

namespace deixis::render {
namespace {

std::string build_error(std::span<const ShaderStage> stages) {
  try {
    ShaderProgram program(stages);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ShaderTest, CompileErrorIsReportedWithTheDriversLog) {
  HeadlessContext context(8, 8);
  const ShaderStage stages[] = {
      {GL_VERTEX_SHADER, "overlay.vert", shader_source("overlay.vert")},
      {GL_FRAGMENT_SHADER, "broken.frag", "out vec4 o;\nvoid main() {\n  o = vec4(1.0) +;\n}\n"}};
  const std::string message = build_error(stages);
  EXPECT_NE(message.find("shader 'broken.frag' (fragment) failed to compile"), std::string::npos)
      << message;
  // Mesa's log names the line (3, thanks to the #line 1 after the prepended #version) and the
  // error.
  EXPECT_NE(message.find("0:3("), std::string::npos) << message;
  EXPECT_NE(message.find("error"), std::string::npos) << message;
}

TEST(ShaderTest, LinkErrorIsReportedWithTheDriversLog) {
  HeadlessContext context(8, 8);
  const ShaderStage stages[] = {
      {GL_VERTEX_SHADER, "plain.vert", "void main() { gl_Position = vec4(0.0); }\n"},
      {GL_FRAGMENT_SHADER, "needs_input.frag",
       "in vec3 v_missing;\nout vec4 o;\nvoid main() { o = vec4(v_missing, 1.0); }\n"}};
  const std::string message = build_error(stages);
  EXPECT_NE(message.find("plain.vert + needs_input.frag failed to link"), std::string::npos)
      << message;
  EXPECT_NE(message.find("v_missing"), std::string::npos) << message;
}

TEST(ShaderTest, EmbeddedSourcesAreThereAndUnknownNamesAreErrors) {
  for (const char* name :
       {"mesh.vert", "lit.frag", "floor.vert", "floor.frag", "overlay.vert", "overlay.frag"}) {
    EXPECT_NE(shader_source(name).find("void main()"), std::string_view::npos) << name;
  }
  EXPECT_THROW(shader_source("missing.frag"), Error);
}

}  // namespace
}  // namespace deixis::render
