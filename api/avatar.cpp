// Avatars through the C API: a glTF/GLB humanoid and the IK solver built for its rig.
#include "api/boundary.h"
#include "api/data_dir.h"
#include "api/handles.h"

using namespace deixis;
using namespace deixis::api;

extern "C" {

deixis_status deixis_avatar_load(uint32_t abi_version, const char* path, deixis_avatar** out,
                                 deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_FILE, [&] {
    check_abi(abi_version);
    require(out != nullptr, "deixis_avatar_load: out is null");
    *out = nullptr;
    const std::filesystem::path file =
        path != nullptr ? std::filesystem::path(path) : data_dir() / "avatars" / "default.glb";
    auto handle = std::make_unique<deixis_avatar>();
    handle->avatar = avatar::load_avatar(file);
    handle->solver = ik::AvatarSolver::build(handle->avatar.rig);
    *out = handle.release();
  });
}

void deixis_avatar_destroy(deixis_avatar* avatar) {
  delete avatar;
}

size_t deixis_avatar_joint_count(const deixis_avatar* avatar) {
  return avatar == nullptr ? 0 : avatar->avatar.rig.skeleton.parents.size();
}

const char* deixis_avatar_joint_name(const deixis_avatar* avatar, size_t joint) {
  if (joint >= deixis_avatar_joint_count(avatar)) {
    return nullptr;
  }
  return avatar->avatar.rig.skeleton.joint_names[joint].c_str();
}

int32_t deixis_avatar_joint_parent(const deixis_avatar* avatar, size_t joint) {
  if (joint >= deixis_avatar_joint_count(avatar)) {
    return -1;
  }
  const std::int16_t parent = avatar->avatar.rig.skeleton.parents[joint];
  return parent < 0 ? -1 : parent;
}

float deixis_avatar_height(const deixis_avatar* avatar) {
  return avatar == nullptr ? 0.0f : avatar->avatar.rig.height;
}

float deixis_avatar_arm_length(const deixis_avatar* avatar) {
  return avatar == nullptr ? 0.0f : avatar->avatar.rig.arm_length;
}

}  // extern "C"
