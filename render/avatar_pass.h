#pragma once
// Skinned avatars, skinned on the GPU: per draw, the joint matrices T_world_model ×
// T_model_joint × inverse bind are composed on the CPU (tens of joints) and sent in one slot of a
// uniform buffer; shaders/mesh.vert blends up to four per vertex.

#include <span>
#include <vector>

#include "render/gpu_mesh.h"
#include "render/programs.h"

namespace deixis::render {

class AvatarPass {
 public:
  static constexpr int kMaxJoints = 256;  // 16 KiB of matrices per avatar

  AvatarPass();
  // Validates and uploads (throws deixis::Error naming the problem).
  SkinnedMeshId add(const SkinnedMesh& mesh);
  // Throws deixis::Error for an unknown mesh or a pose with the wrong number of joints.
  void draw(std::span<const AvatarDraw> avatars, const Mat4& view_projection,
            const RendererOptions& options);

  const GpuSkinnedMesh& mesh(SkinnedMeshId id) const { return meshes_[id.index]; }

 private:
  void reserve_slots(std::size_t count);

  LitProgram lit_;
  std::vector<GpuSkinnedMesh> meshes_;
  GlBuffer joint_buffer_;
  GLsizeiptr slot_bytes_ = 0;  // one avatar's matrices, rounded up to the offset alignment
  std::size_t slots_ = 0;
  std::vector<Eigen::Matrix4f> joint_matrices_;  // staging, sized by add()
};

}  // namespace deixis::render
