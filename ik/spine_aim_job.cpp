#include "ik/spine_aim_job.h"

#include "ik/job_validation.h"
#include "ik/joint_rotation.h"
#include "ik/rotations.h"

namespace deixis::ik {

bool SpineAimJob::validate(std::string_view* reason) const {
  if (!validate_chain(skeleton, chain, weights, max_angles, local, model, kMaxChain, reason)) {
    return false;
  }
  if (weights.back() != 1.0f) {
    return fail(reason, "the last chain joint's weight must be 1");
  }
  return true;
}

bool SpineAimJob::run() const {
  if (!validate()) {
    return false;
  }
  const int aimed = chain.back();
  if (!target.allFinite()) {
    if (reached != nullptr) {
      *reached = false;
    }
    return true;
  }
  const Mat3 R_target = orthonormalized(target);
  // Each turn carries the aimed joint with it; following it saves recomputing the path to it
  // after every joint (only the path to the next chain joint is needed).
  Mat3 R_aimed = model[aimed].rotation;
  for (std::size_t k = 0; k < chain.size(); ++k) {
    const Mat3 error = R_target * R_aimed.transpose();
    const int next = k + 1 < chain.size() ? chain[k + 1] : aimed;
    R_aimed = rotate_joint_limited(*skeleton, local, model, chain[k],
                                   scale_rotation(error, weights[k]), max_angles[k], next) *
              R_aimed;
  }
  if (reached != nullptr) {
    *reached = rotation_angle(R_target * model[aimed].rotation.transpose()) < deg(0.01f);
  }
  return true;
}

}  // namespace deixis::ik
