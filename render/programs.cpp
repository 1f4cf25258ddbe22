#include "render/programs.h"

#include <string>

#include "render/shader_sources.h"

namespace deixis::render {

LitProgram lit_program(bool skinned, int max_joints) {
  const ShaderStage stages[] = {{GL_VERTEX_SHADER, "mesh.vert", shader_source("mesh.vert")},
                                {GL_FRAGMENT_SHADER, "lit.frag", shader_source("lit.frag")}};
  const std::string defines =
      skinned ? "#define SKINNED 1\n#define MAX_JOINTS " + std::to_string(max_joints) + "\n" : "";
  LitProgram lit{ShaderProgram(stages, defines)};
  lit.view_projection = lit.program.uniform("u_view_projection");
  lit.model = lit.program.uniform("u_model");
  lit.normal_matrix = lit.program.uniform("u_normal_matrix");
  lit.colour = lit.program.uniform("u_colour");
  lit.light_direction = lit.program.uniform("u_light_direction");
  lit.ambient = lit.program.uniform("u_ambient");
  return lit;
}

void set_frame_uniforms(const LitProgram& lit, const Mat4& view_projection,
                        const RendererOptions& options) {
  const GLuint p = lit.program.id();
  const Vec3 light = options.light_direction.normalized();
  glProgramUniformMatrix4fv(p, lit.view_projection, 1, GL_FALSE, view_projection.data());
  glProgramUniform3fv(p, lit.light_direction, 1, light.data());
  glProgramUniform1f(p, lit.ambient, options.ambient);
}

OverlayProgram overlay_program() {
  const ShaderStage stages[] = {
      {GL_VERTEX_SHADER, "overlay.vert", shader_source("overlay.vert")},
      {GL_FRAGMENT_SHADER, "overlay.frag", shader_source("overlay.frag")}};
  OverlayProgram overlay{ShaderProgram(stages)};
  overlay.view_projection = overlay.program.uniform("u_view_projection");
  overlay.model = overlay.program.uniform("u_model");
  return overlay;
}

}  // namespace deixis::render
