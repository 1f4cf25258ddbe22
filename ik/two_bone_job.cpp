#include "ik/two_bone_job.h"

#include <algorithm>
#include <cmath>

#include "ik/job_validation.h"

namespace deixis::ik {
namespace {

// A correction that changes nothing: used for degenerate chains and non-finite targets.
void write_identity(const TwoBoneJob& job) {
  *job.start_correction = Mat3::Identity();
  *job.mid_correction = Mat3::Identity();
  if (job.reached != nullptr) {
    *job.reached = false;
  }
  if (job.end_position != nullptr) {
    *job.end_position = job.end_joint->translation;
  }
}

}  // namespace

Reach reach_of(float a, float b, const HingeRange& flexion) {
  const auto distance = [&](float flex) {
    return std::sqrt(std::max(0.0f, a * a + b * b + 2.0f * a * b * std::cos(flex)));
  };
  return {distance(flexion.max), distance(flexion.min)};
}

float soft_reach(float d, float soft_start, float max) {
  const float band = max - soft_start;
  if (d <= soft_start || band <= kTinyLength) {
    return std::min(d, max);
  }
  return soft_start + band * (1.0f - std::exp(-(d - soft_start) / band));
}

bool TwoBoneJob::validate(std::string_view* reason) const {
  if (start_joint == nullptr) {
    return fail(reason, "start_joint is not set");
  }
  if (mid_joint == nullptr) {
    return fail(reason, "mid_joint is not set");
  }
  if (end_joint == nullptr) {
    return fail(reason, "end_joint is not set");
  }
  if (start_correction == nullptr) {
    return fail(reason, "start_correction output is not set");
  }
  if (mid_correction == nullptr) {
    return fail(reason, "mid_correction output is not set");
  }
  if (!(std::abs(mid_axis.norm() - 1.0f) < 1e-3f)) {
    return fail(reason, "mid_axis is not a unit vector");
  }
  if (!(soften > 0.0f && soften <= 1.0f)) {
    return fail(reason, "soften is not in (0, 1]");
  }
  if (!(flexion.min >= 0.0f && flexion.min <= flexion.max && flexion.max <= kPi)) {
    return fail(reason, "flexion range is not ordered within [0, π]");
  }
  return true;
}

bool TwoBoneJob::run() const {
  if (!validate()) {
    return false;
  }
  const Vec3 S = start_joint->translation;
  const Vec3 E = mid_joint->translation;
  const Vec3 W = end_joint->translation;
  const float a = (E - S).norm();
  const float b = (W - E).norm();
  if (!(a > kTinyLength && b > kTinyLength) || !target.allFinite() || !is_finite(*start_joint) ||
      !is_finite(*mid_joint) || !is_finite(*end_joint)) {
    write_identity(*this);
    return true;
  }
  const Vec3 upper = (E - S) / a;
  const Vec3 lower = (W - E) / b;
  const Vec3 hinge = mid_joint->rotation * mid_axis;

  // Where the end goes: along the start→target ray, at the distance the chain can reach.
  const Reach reach = reach_of(a, b, flexion);
  const float soft_start = std::max(soften * reach.max, reach.min);
  const Vec3 to_target = target - S;
  const float d = robust_norm(to_target);
  const Vec3 u = d > kTinyLength ? Vec3(to_target / d) : normalized_or(W - S, upper);
  const float reached_distance =
      std::clamp(soft_reach(d, soft_start, reach.max), reach.min, reach.max);

  // The side the mid joint bends to: the pole, made perpendicular to the ray. A pole along the
  // ray (or not finite) keeps the chain's current hinge.
  Vec3 v = pole_vector - pole_vector.dot(u) * u;
  if (!(v.allFinite() && v.norm() > 1e-4f)) {
    v = u.cross(hinge);
    v -= v.dot(u) * u;
  }
  v = normalized_or(v, any_perpendicular(u));
  v = (v - v.dot(u) * u).normalized();  // again: a pole nearly along the ray leaves round-off
  const Vec3 new_hinge = v.cross(u);

  // Law of cosines at the start joint.
  const float cos_start = reached_distance > kTinyLength
                              ? std::clamp((a * a + reached_distance * reached_distance - b * b) /
                                               (2.0f * a * reached_distance),
                                           -1.0f, 1.0f)
                              : 0.0f;
  const float sin_start = std::sqrt(std::max(0.0f, 1.0f - cos_start * cos_start));
  const Vec3 new_upper = cos_start * u + sin_start * v;
  const Vec3 new_mid = S + a * new_upper;
  const Vec3 new_end = S + reached_distance * u;
  const Vec3 new_lower = normalized_or(new_end - new_mid, new_upper);

  // Each bone's frame (bone direction, hinge) maps onto its new frame.
  const Mat3 C_start = frame_from(new_upper, new_hinge) * frame_from(upper, hinge).transpose();
  const Mat3 C_mid =
      frame_from(new_lower, new_hinge) * frame_from(C_start * lower, C_start * hinge).transpose();
  const Mat3& R_start = start_joint->rotation;
  const Mat3& R_mid = mid_joint->rotation;
  *start_correction = R_start.transpose() * C_start * R_start;
  *mid_correction = R_mid.transpose() * C_start.transpose() * C_mid * C_start * R_mid;
  if (reached != nullptr) {
    *reached = std::abs(reached_distance - d) < 1e-4f;
  }
  if (end_position != nullptr) {
    *end_position = new_end;
  }
  return true;
}

}  // namespace deixis::ik
