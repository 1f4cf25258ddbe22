#pragma once
// The renderer's shader programs, built from the embedded shaders/ sources, with their uniform
// locations looked up once.

#include "render/scene.h"
#include "render/shader.h"

namespace deixis::render {

// shaders/mesh.vert + lit.frag: rigid target objects, or (skinned) avatars.
struct LitProgram {
  ShaderProgram program;
  GLint view_projection = -1;
  GLint model = -1;          // rigid only
  GLint normal_matrix = -1;  // rigid only
  GLint colour = -1;
  GLint light_direction = -1;
  GLint ambient = -1;
};
LitProgram lit_program(bool skinned, int max_joints);
// Sets what is the same for every draw of a frame: camera and light.
void set_frame_uniforms(const LitProgram& lit, const Mat4& view_projection,
                        const RendererOptions& options);

// shaders/overlay.*: labels and debug lines.
struct OverlayProgram {
  ShaderProgram program;
  GLint view_projection = -1;
  GLint model = -1;
};
OverlayProgram overlay_program();

// The uniform binding point of mesh.vert's JointMatrices block.
inline constexpr GLuint kJointMatricesBinding = 0;

}  // namespace deixis::render
