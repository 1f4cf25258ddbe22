#pragma once
// Skinned avatars, skinned on the GPU: per draw, the joint matrices T_world_model ×
// T_model_joint × inverse bind are composed on the CPU (tens of joints) and sent in one slot of a
// uniform buffer; shaders/mesh.vert blends up to four per vertex. Opaque avatars are drawn first;
// one with opacity below 1 then gets a depth-only pass and a blended pass (premultiplied colour,
// so a see-through headset's layer gets the right alpha), which shows only its nearest surface:
// a fading avatar looks like a fading body, not a glass one with its far arm showing through.

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
  // Composes and uploads avatar a's joint matrices into its slot and binds them and its mesh.
  const GpuSkinnedMesh& bind(std::size_t a, const AvatarDraw& avatar);
  void draw_primitives(const GpuSkinnedMesh& mesh, float opacity) const;

  LitProgram lit_;
  std::vector<GpuSkinnedMesh> meshes_;
  GlBuffer joint_buffer_;
  GLsizeiptr slot_bytes_ = 0;  // one avatar's matrices, rounded up to the offset alignment
  std::size_t slots_ = 0;
  std::vector<Eigen::Matrix4f> joint_matrices_;  // staging, sized by add()
};

}  // namespace deixis::render
