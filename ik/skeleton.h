#pragma once
// A skeleton as a flat array of joints in depth-first order (after ozz-animation): every joint's
// parent comes before it, so "local to model" is one forward loop. Poses use Deixis' world
// conventions: +Y up, and a humanoid in its rest pose faces −Z (glTF's +Z-facing assets are turned
// once at load).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/math/pose.h"

namespace deixis::ik {

inline constexpr std::int16_t kNoParent = -1;

struct Skeleton {
  std::vector<std::string> joint_names;
  std::vector<std::int16_t> parents;  // parents[i] < i, or kNoParent for a root
  std::vector<Pose> rest_local;       // T_parent_joint in the rest (bind) pose

  int joint_count() const { return static_cast<int>(parents.size()); }
  int find(std::string_view name) const;  // −1 when absent
};

// Checks the depth-first invariant and sizes; throws deixis::Error naming the first bad joint.
void validate(const Skeleton& skeleton, std::string_view source);

// T_model_joint for every joint from T_parent_joint (ozz's LocalToModelJob): one forward loop, no
// allocation. `model` and `local` must both hold joint_count() poses.
void local_to_model(const Skeleton& skeleton, std::span<const Pose> local, std::span<Pose> model);

// T_model_joint of every joint in the rest pose (allocates: load time only).
std::vector<Pose> rest_model_poses(const Skeleton& skeleton);

// True when `ancestor` is `joint` or one of its ancestors.
bool is_ancestor(const Skeleton& skeleton, int ancestor, int joint);

// After the local poses of joints between `from` and `joint` changed, recomputes T_model_joint for
// the joints on the path from `from` (an ancestor of `joint`, or `joint` itself) down to `joint`
// only, so IK jobs stay cheap on skeletons with many fingers. model[parent of `from`] must be
// current; other joints are left as they were. No allocation.
void update_model_path(const Skeleton& skeleton, std::span<const Pose> local, std::span<Pose> model,
                       int from, int joint);

}  // namespace deixis::ik
