#include "ik/index_finger_job.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ik/job_validation.h"

namespace deixis::ik {
namespace {

constexpr float kTolerance = 1e-5f;  // m: a tip this close is on the target
constexpr int kRootSteps = 12;       // regula falsi steps for the curl (usually 3 to 6 suffice)

// The flexion of curled joint k at curl fraction c ∈ [0, 1].
float curled(const HingeRange& range, float c) {
  return std::clamp(c * range.max, range.min, range.max);
}

}  // namespace

bool IndexFingerJob::validate(std::string_view* reason) const {
  if (skeleton == nullptr) {
    return fail(reason, "skeleton is not set");
  }
  const auto n = static_cast<std::size_t>(skeleton->joint_count());
  if (local.size() != n || model.size() != n) {
    return fail(reason, "local and model must hold one pose per skeleton joint");
  }
  if (chain.empty() || chain.size() > kMaxFingerJoints) {
    return fail(reason, "chain must hold 1 to 3 joints");
  }
  if (flexion_axes.size() != chain.size() || flexion.size() != chain.size()) {
    return fail(reason, "flexion_axes and flexion must hold one entry per chain joint");
  }
  for (std::size_t k = 0; k < chain.size(); ++k) {
    if (!valid_joint(*skeleton, chain[k])) {
      return fail(reason, "chain joint is not a joint of the skeleton");
    }
    if (k > 0 && skeleton->parents[chain[k]] != chain[k - 1]) {
      return fail(reason, "each chain joint must be the parent of the next");
    }
    if (!(std::abs(flexion_axes[k].norm() - 1.0f) < 1e-3f)) {
      return fail(reason, "flexion_axes must be unit vectors");
    }
    if (!(flexion[k].min >= -kPi && flexion[k].min <= flexion[k].max && flexion[k].max <= kPi)) {
      return fail(reason, "flexion ranges must be ordered within [−π, π]");
    }
  }
  if (!tip_offset.allFinite()) {
    return fail(reason, "tip_offset is not finite");
  }
  return true;
}

bool IndexFingerJob::run() const {
  if (!validate()) {
    return false;
  }
  const int first = chain.front();
  const int last = chain.back();
  const std::size_t n = chain.size();
  const auto tip_now = [&] { return transform_point(model[last], tip_offset); };
  const auto hinge = [&](std::size_t k, float angle) {
    return Mat3(skeleton->rest_local[chain[k]].rotation * axis_angle(flexion_axes[k], angle));
  };

  if (target.allFinite() && (tip_now() - target).norm() > kTolerance) {
    // 1. The curl: the fingertip's distance from the first joint shrinks as the finger curls.
    const auto tip_in_first = [&](float c) {
      Vec3 p = tip_offset;
      for (std::size_t k = n; k-- > 1;) {
        p = hinge(k, curled(flexion[k], c)) * p + skeleton->rest_local[chain[k]].translation;
      }
      return p;
    };
    const float wanted = (target - model[first].translation).norm();
    float curl = 0.0f;
    if (n > 1) {
      // Regula falsi (Illinois) on f(c) = |tip(c)| − wanted, which falls as the finger curls: a
      // few evaluations instead of the dozens bisection takes.
      float lo = 0.0f, hi = 1.0f;
      float f_lo = tip_in_first(lo).norm() - wanted;
      float f_hi = tip_in_first(hi).norm() - wanted;
      if (f_hi >= 0.0f) {
        curl = 1.0f;  // nearer than the fully curled finger reaches: curl all the way
      } else if (f_lo > 0.0f) {
        int side = 0;
        for (int i = 0; i < kRootSteps && hi - lo > 1e-6f; ++i) {
          curl = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
          const float f = tip_in_first(curl).norm() - wanted;
          if (std::abs(f) < 1e-6f) {
            break;
          }
          if (f > 0.0f) {
            lo = curl;
            f_lo = f;
            f_hi = side == 1 ? 0.5f * f_hi : f_hi;
            side = 1;
          } else {
            hi = curl;
            f_hi = f;
            f_lo = side == -1 ? 0.5f * f_lo : f_lo;
            side = -1;
          }
        }
      }
    }
    for (std::size_t k = 1; k < n; ++k) {
      local[chain[k]].rotation = hinge(k, curled(flexion[k], curl));
    }
    update_model_path(*skeleton, local, model, first, last);

    // 2. The first joint points the finger: the turn about its axis that carries the tip's
    // direction onto the target's (as seen across the axis).
    const Vec3 axis = model[first].rotation * flexion_axes[0];
    Vec3 to_tip = tip_now() - model[first].translation;
    Vec3 to_target = target - model[first].translation;
    to_tip -= to_tip.dot(axis) * axis;
    to_target -= to_target.dot(axis) * axis;
    if (to_tip.norm() > kTinyLength && to_target.norm() > kTinyLength) {
      const Mat3& L0 = skeleton->rest_local[first].rotation;
      const float current =
          swing_twist(rest_deviation(local[first].rotation, L0), flexion_axes[0]).twist;
      const float turn = std::atan2(to_tip.cross(to_target).dot(axis), to_tip.dot(to_target));
      local[first].rotation = hinge(0, std::clamp(current + turn, flexion[0].min, flexion[0].max));
      update_model_path(*skeleton, local, model, first, last);
    }
  }
  const Vec3 end = tip_now();
  if (reached != nullptr) {
    *reached = target.allFinite() && (end - target).norm() < 1e-3f;
  }
  if (tip != nullptr) {
    *tip = end;
  }
  return true;
}

}  // namespace deixis::ik
