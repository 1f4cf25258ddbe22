#include "ik/lean_job.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>

#include "ik/job_validation.h"
#include "ik/joint_rotation.h"
#include "ik/rotations.h"
#include "ik/spine_aim_job.h"

namespace deixis::ik {
namespace {

constexpr float kTolerance = 1e-4f;  // m: a point this close needs no further step
// Levenberg–Marquardt damping, relative to the chain's size: it starts high, so the first step
// stays small where the pivots barely change the point's distance (they are nearly in line with
// it), falls tenfold after every step that brings the point nearer and rises threefold (the step
// undone) after one that does not.
constexpr float kDamping = 1e-2f;
constexpr float kMinDamping = 1e-8f;
constexpr float kStall = 0.1f;  // an accepted step that gains less than 10 % ends the search

}  // namespace

bool LeanJob::validate(std::string_view* reason) const {
  if (!validate_chain(skeleton, chain, weights, max_angles, local, model, kMaxChain, reason)) {
    return false;
  }
  if (weights.back() != 1.0f) {
    return fail(reason, "the last pivot's weight must be 1");
  }
  if (!valid_joint(*skeleton, end_joint) || !is_ancestor(*skeleton, chain.back(), end_joint)) {
    return fail(reason, "end_joint must be a joint at or below the last pivot");
  }
  if (!end_offset.allFinite()) {
    return fail(reason, "end_offset is not finite");
  }
  if (iterations < 1 || iterations > 16) {
    return fail(reason, "iterations must lie in 1..16");
  }
  return true;
}

bool LeanJob::run() const {
  if (!validate()) {
    return false;
  }
  const auto point = [&] { return transform_point(model[end_joint], end_offset); };
  std::array<Mat3, kMaxChain> saved{};
  float damping = kDamping;
  float error_now = target.allFinite() ? (point() - target).norm() : 0.0f;
  for (int it = 0; it < iterations && error_now > kTolerance; ++it) {
    const Vec3 x = point();
    const Vec3 e = target - x;
    // Damped least squares: a small turn ω_k at pivot P_k moves the point by ω_k × (x − P_k).
    // The turns of least weighted size (weight = mobility) that move it by e are
    // ω_k = w_k · r_k × y with (Σ w_k [r_k]×[r_k]×ᵀ + λ²) y = e.
    std::array<Vec3, kMaxChain> lever{};  // r_k, before any turn of this step
    Mat3 A = Mat3::Zero();
    float scale = 0.0f;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const Vec3 r = x - model[chain[k]].translation;
      lever[k] = r;
      A += weights[k] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
      scale += weights[k] * r.squaredNorm();
      saved[k] = local[chain[k]].rotation;
    }
    if (!(scale > kTinyLength)) {
      break;  // the point sits on every pivot: nothing turns it
    }
    A += damping * scale * Mat3::Identity();
    const Vec3 y = A.ldlt().solve(e);
    // Each pivot's turn; the path is recomputed only down to the next pivot, and from the last
    // one down to the point.
    for (std::size_t k = 0; k < chain.size(); ++k) {
      const Vec3 omega = weights[k] * lever[k].cross(y);
      const float angle = omega.norm();
      const int next = k + 1 < chain.size() ? chain[k + 1] : end_joint;
      if (angle > 1e-9f && std::isfinite(angle)) {
        rotate_joint_limited(*skeleton, local, model, chain[k], axis_angle(omega / angle, angle),
                             max_angles[k], next);
      } else {
        update_model_path(*skeleton, local, model, chain[k], next);
      }
    }
    const float error_new = (point() - target).norm();
    if (error_new < error_now) {
      // Accepted: trust the linear model more. A step that gains little means H is at what the
      // chain can reach (the rest of the error lies along the pivots' lines): stop there.
      const bool stalled = error_now - error_new < kStall * error_now;
      error_now = error_new;
      damping = std::max(damping * 0.1f, kMinDamping);
      if (stalled) {
        break;
      }
    } else {
      for (std::size_t k = 0; k < chain.size(); ++k) {  // rejected: undo, trust it less
        local[chain[k]].rotation = saved[k];
      }
      update_model_path(*skeleton, local, model, chain.front(), end_joint);
      damping *= 3.0f;
    }
  }
  const float distance = target.allFinite() ? (point() - target).norm() : -1.0f;
  if (reached != nullptr) {
    *reached = distance >= 0.0f && distance < 1e-3f;
  }
  if (error != nullptr) {
    *error = distance;
  }
  return true;
}

}  // namespace deixis::ik
