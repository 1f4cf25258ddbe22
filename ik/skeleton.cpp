#include "ik/skeleton.h"

#include <array>

#include "core/error.h"

namespace deixis::ik {

int Skeleton::find(std::string_view name) const {
  for (int i = 0; i < joint_count(); ++i) {
    if (joint_names[i] == name) {
      return i;
    }
  }
  return -1;
}

void validate(const Skeleton& skeleton, std::string_view source) {
  const std::size_t n = skeleton.parents.size();
  if (skeleton.joint_names.size() != n || skeleton.rest_local.size() != n) {
    throw Error(std::string(source) + ": skeleton has " + std::to_string(n) + " parents, " +
                std::to_string(skeleton.joint_names.size()) + " names and " +
                std::to_string(skeleton.rest_local.size()) + " rest poses");
  }
  if (n == 0 || n > 1024) {
    throw Error(std::string(source) + ": skeleton has " + std::to_string(n) +
                " joints (expected 1 to 1024)");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const int parent = skeleton.parents[i];
    if (parent != kNoParent && (parent < 0 || parent >= static_cast<int>(i))) {
      throw Error(std::string(source) + ": joint '" + skeleton.joint_names[i] + "' has parent " +
                  std::to_string(parent) + ", not an earlier joint (depth-first order)");
    }
    if (!is_finite(skeleton.rest_local[i])) {
      throw Error(std::string(source) + ": joint '" + skeleton.joint_names[i] +
                  "' has a non-finite rest pose");
    }
  }
}

void local_to_model(const Skeleton& skeleton, std::span<const Pose> local, std::span<Pose> model) {
  const int n = skeleton.joint_count();
  for (int i = 0; i < n; ++i) {
    const int parent = skeleton.parents[i];
    model[i] = parent == kNoParent ? local[i] : compose(model[parent], local[i]);
  }
}

std::vector<Pose> rest_model_poses(const Skeleton& skeleton) {
  std::vector<Pose> model(skeleton.rest_local.size());
  local_to_model(skeleton, skeleton.rest_local, model);
  return model;
}

bool is_ancestor(const Skeleton& skeleton, int ancestor, int joint) {
  for (int j = joint; j != kNoParent; j = skeleton.parents[j]) {
    if (j == ancestor) {
      return true;
    }
  }
  return false;
}

void update_model_path(const Skeleton& skeleton, std::span<const Pose> local, std::span<Pose> model,
                       int from, int joint) {
  // The path is at most as deep as a humanoid limb; walk it upward into a fixed array, then
  // recompute downward. A deeper path (unheard of in humanoids) recomputes the whole index range
  // [from, joint] instead, which depth-first order makes correct too.
  constexpr int kMaxDepth = 64;
  // Only path[0, n) is read, so it is not zero-filled: filling 64 ints on every call was 3 % of a
  // whole avatar's solve (ik_bench's BM_AvatarSolve, 8.8 → 8.5 µs).
  std::array<int, kMaxDepth> path;
  int n = 0;
  int j = joint;
  while (j != from && j != kNoParent && n < kMaxDepth) {
    path[n++] = j;
    j = skeleton.parents[j];
  }
  if (j != from || n == kMaxDepth) {
    for (int i = from; i <= joint; ++i) {
      const int parent = skeleton.parents[i];
      model[i] = parent == kNoParent ? local[i] : compose(model[parent], local[i]);
    }
    return;
  }
  const auto update = [&](int i) {
    const int parent = skeleton.parents[i];
    model[i] = parent == kNoParent ? local[i] : compose(model[parent], local[i]);
  };
  update(from);
  for (int k = n - 1; k >= 0; --k) {
    update(path[k]);
  }
}

}  // namespace deixis::ik
