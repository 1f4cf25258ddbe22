#include "render/floor_pass.h"

#include "render/shader_sources.h"

namespace deixis::render {
namespace {

ShaderProgram floor_program() {
  const ShaderStage stages[] = {{GL_VERTEX_SHADER, "floor.vert", shader_source("floor.vert")},
                                {GL_FRAGMENT_SHADER, "floor.frag", shader_source("floor.frag")}};
  return ShaderProgram(stages);
}

}  // namespace

FloorPass::FloorPass() : program_(floor_program()), no_vertices_(create_vertex_array()) {
  uniform_.view_projection = program_.uniform("u_view_projection");
  uniform_.extent = program_.uniform("u_extent");
  uniform_.height = program_.uniform("u_height");
  uniform_.spacing = program_.uniform("u_spacing");
  uniform_.camera_position = program_.uniform("u_camera_position");
  uniform_.floor_colour = program_.uniform("u_floor_colour");
  uniform_.grid_colour = program_.uniform("u_grid_colour");
  uniform_.background = program_.uniform("u_background");
}

void FloorPass::draw(const Mat4& view_projection, const Vec3& camera_position,
                     const RendererOptions& options) const {
  const GLuint p = program_.id();
  glProgramUniformMatrix4fv(p, uniform_.view_projection, 1, GL_FALSE, view_projection.data());
  glProgramUniform1f(p, uniform_.extent, options.floor_extent);
  glProgramUniform1f(p, uniform_.height, options.floor_height);
  glProgramUniform1f(p, uniform_.spacing, options.grid_spacing);
  glProgramUniform3fv(p, uniform_.camera_position, 1, camera_position.data());
  glProgramUniform4fv(p, uniform_.floor_colour, 1, options.floor_colour.data());
  glProgramUniform4fv(p, uniform_.grid_colour, 1, options.grid_colour.data());
  glProgramUniform4fv(p, uniform_.background, 1, options.background.data());
  glUseProgram(p);
  glBindVertexArray(no_vertices_.get());
  glDisable(GL_CULL_FACE);  // seen from above or, by a camera below the floor, from below
  glDrawArrays(GL_TRIANGLES, 0, 6);
}

}  // namespace deixis::render
