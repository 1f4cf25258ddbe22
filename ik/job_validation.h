#pragma once
// Validation rules the IK jobs share, so that every job words the same rule the same way.

#include <span>
#include <string_view>

#include "ik/skeleton.h"

namespace deixis::ik {

// True when `joint` indexes the skeleton.
inline bool valid_joint(const Skeleton& skeleton, int joint) {
  return joint >= 0 && joint < skeleton.joint_count();
}

// A chain of the spine jobs (spine aim, lean): 1..max_chain joints, each an ancestor of the next,
// weights in [0, 1], limits in [0, π], and pose spans of the skeleton's size.
// True when the chain can be solved; otherwise false with *reason naming the rule.
bool validate_chain(const Skeleton* skeleton, std::span<const int> chain,
                    std::span<const float> weights, std::span<const float> max_angles,
                    std::span<const Pose> local, std::span<const Pose> model, int max_chain,
                    std::string_view* reason);

// Sets *reason (when given) and returns false: the common tail of every validate().
inline bool fail(std::string_view* reason, std::string_view why) {
  if (reason != nullptr) {
    *reason = why;
  }
  return false;
}

}  // namespace deixis::ik
