#pragma once
// The floor square with its grid (shaders/floor.*).

#include "render/gl_object.h"
#include "render/scene.h"
#include "render/shader.h"

namespace deixis::render {

class FloorPass {
 public:
  FloorPass();
  void draw(const Mat4& view_projection, const Vec3& camera_position,
            const RendererOptions& options) const;

 private:
  ShaderProgram program_;
  GlVertexArray no_vertices_;  // core profile draws need a vertex array, even an empty one
  struct {
    GLint view_projection, extent, height, spacing, camera_position, floor_colour, grid_colour,
        background;
  } uniform_{};
};

}  // namespace deixis::render
