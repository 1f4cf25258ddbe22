#include "ik/job_validation.h"

#include "ik/rotations.h"

namespace deixis::ik {

bool validate_chain(const Skeleton* skeleton, std::span<const int> chain,
                    std::span<const float> weights, std::span<const float> max_angles,
                    std::span<const Pose> local, std::span<const Pose> model, int max_chain,
                    std::string_view* reason) {
  if (skeleton == nullptr) {
    return fail(reason, "skeleton is not set");
  }
  const auto n = static_cast<std::size_t>(skeleton->joint_count());
  if (local.size() != n || model.size() != n) {
    return fail(reason, "local and model must hold one pose per skeleton joint");
  }
  if (chain.empty() || chain.size() > static_cast<std::size_t>(max_chain)) {
    return fail(reason, "chain must hold 1 to kMaxChain joints");
  }
  if (weights.size() != chain.size() || max_angles.size() != chain.size()) {
    return fail(reason, "weights and max_angles must hold one value per chain joint");
  }
  for (std::size_t k = 0; k < chain.size(); ++k) {
    if (!valid_joint(*skeleton, chain[k])) {
      return fail(reason, "chain joint is not a joint of the skeleton");
    }
    if (k > 0 && (chain[k] == chain[k - 1] || !is_ancestor(*skeleton, chain[k - 1], chain[k]))) {
      return fail(reason, "chain joints must be ancestors of the joints after them");
    }
    if (!(weights[k] >= 0.0f && weights[k] <= 1.0f)) {
      return fail(reason, "weights must lie in [0, 1]");
    }
    if (!(max_angles[k] >= 0.0f && max_angles[k] <= kPi)) {
      return fail(reason, "max_angles must lie in [0, π]");
    }
  }
  return true;
}

}  // namespace deixis::ik
