#include "render/avatar_pass.h"

#include <array>
#include <string>

#include "core/error.h"

namespace deixis::render {

AvatarPass::AvatarPass() : lit_(lit_program(true, kMaxJoints)), joint_buffer_(create_buffer()) {
  GLint alignment = 1;
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &alignment);
  const GLsizeiptr block = kMaxJoints * static_cast<GLsizeiptr>(sizeof(Eigen::Matrix4f));
  slot_bytes_ = (block + alignment - 1) / alignment * alignment;
}

SkinnedMeshId AvatarPass::add(const SkinnedMesh& mesh) {
  meshes_.push_back(upload(mesh, kMaxJoints));
  if (joint_matrices_.size() < mesh.inverse_bind.size()) {
    joint_matrices_.resize(mesh.inverse_bind.size());
  }
  return {static_cast<int>(meshes_.size()) - 1};
}

void AvatarPass::reserve_slots(std::size_t count) {
  if (count <= slots_) {
    return;
  }
  slots_ = count;
  glNamedBufferData(joint_buffer_.get(), slot_bytes_ * static_cast<GLsizeiptr>(slots_), nullptr,
                    GL_DYNAMIC_DRAW);
}

void AvatarPass::draw(std::span<const AvatarDraw> avatars, const Mat4& view_projection,
                      const RendererOptions& options) {
  if (avatars.empty()) {
    return;
  }
  // Each avatar gets its own slot, so no draw waits for the previous one to read its matrices.
  reserve_slots(avatars.size());
  set_frame_uniforms(lit_, view_projection, options);
  glUseProgram(lit_.program.id());
  glEnable(GL_CULL_FACE);
  bool fading = false;
  for (std::size_t a = 0; a < avatars.size(); ++a) {
    if (avatars[a].opacity >= 1.0f) {
      draw_primitives(bind(a, avatars[a]), 1.0f);
    } else {
      fading = true;
    }
  }
  if (!fading) {
    return;
  }
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied (draw_primitives)
  glDepthFunc(GL_LEQUAL);
  for (std::size_t a = 0; a < avatars.size(); ++a) {
    const float opacity = avatars[a].opacity;
    if (opacity >= 1.0f || !(opacity > 0.0f)) {
      continue;  // drawn above, or not at all
    }
    const GpuSkinnedMesh& mesh = bind(a, avatars[a]);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);  // its nearest surface's depth
    draw_primitives(mesh, 1.0f);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);  // that surface, blended
    draw_primitives(mesh, opacity);
  }
  glDepthFunc(GL_LESS);
  glDisable(GL_BLEND);
}

const GpuSkinnedMesh& AvatarPass::bind(std::size_t a, const AvatarDraw& avatar) {
  if (avatar.mesh.index < 0 || avatar.mesh.index >= static_cast<int>(meshes_.size())) {
    throw Error("renderer: avatar " + std::to_string(a) + " has unknown mesh id " +
                std::to_string(avatar.mesh.index));
  }
  const GpuSkinnedMesh& mesh = meshes_[avatar.mesh.index];
  const std::size_t joints = mesh.inverse_bind.size();
  if (avatar.T_model_joint.size() != joints) {
    throw Error("renderer: avatar " + std::to_string(a) + " has " +
                std::to_string(avatar.T_model_joint.size()) + " joint poses, its mesh " +
                std::to_string(joints) + " joints");
  }
  for (std::size_t j = 0; j < joints; ++j) {
    // The skinning transform of joint j: bind-pose model frame to the world.
    const Pose T_world_bind =
        compose(compose(avatar.T_world_model, avatar.T_model_joint[j]), mesh.inverse_bind[j]);
    Eigen::Matrix4f& m = joint_matrices_[j];
    m.setIdentity();
    m.topLeftCorner<3, 3>() = T_world_bind.rotation;
    m.topRightCorner<3, 1>() = T_world_bind.translation;
  }
  const GLintptr offset = slot_bytes_ * static_cast<GLintptr>(a);
  glNamedBufferSubData(joint_buffer_.get(), offset,
                       static_cast<GLsizeiptr>(joints * sizeof(Eigen::Matrix4f)),
                       joint_matrices_.data());
  glBindBufferRange(GL_UNIFORM_BUFFER, kJointMatricesBinding, joint_buffer_.get(), offset,
                    slot_bytes_);
  glBindVertexArray(mesh.geometry.vertex_array.get());
  return mesh;
}

// Each primitive in its base colour, premultiplied by `opacity` (shaders/lit.frag lights the
// colour and passes its alpha through).
void AvatarPass::draw_primitives(const GpuSkinnedMesh& mesh, float opacity) const {
  const GLuint p = lit_.program.id();
  for (const SkinnedPrimitive& primitive : mesh.primitives) {
    const std::array<float, 4>& c = primitive.base_color;
    const std::array<float, 4> colour{c[0] * opacity, c[1] * opacity, c[2] * opacity,
                                      c[3] * opacity};
    glProgramUniform4fv(p, lit_.colour, 1, colour.data());
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(primitive.index_count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(std::uintptr_t{primitive.first_index} *
                                                 sizeof(std::uint32_t)));
  }
}

}  // namespace deixis::render
