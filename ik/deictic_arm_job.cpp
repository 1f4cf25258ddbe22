#include "ik/deictic_arm_job.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ik/index_finger_job.h"
#include "ik/job_validation.h"
#include "ik/rotations.h"
#include "ik/two_bone_job.h"  // reach_of, soft_reach

namespace deixis::ik {
namespace {

constexpr int kPlacementRounds = 4;

// Where the wrist goes and how the hand is turned so that the fingertip (offset c in the hand's
// frame) lands on target t, for an arm whose wrist reaches distances `reach` from shoulder S.
struct Placement {
  Vec3 wrist;
  Mat3 hand;
  bool beyond_reach;
};

Placement place_wrist(const Vec3& S, const Vec3& t, const Mat3& R, const Vec3& c,
                      const Reach& reach, float soft_start, const Vec3& fallback_direction) {
  const Vec3 wrist_to_tip = R * c;
  const Vec3 p = t - wrist_to_tip;  // the wrist for the wanted orientation
  const float d_w = (p - S).norm();
  if (d_w >= reach.min && d_w <= soft_start) {
    return {p, R, false};
  }
  // The wrist cannot go to p: it goes to the sphere of radius r the arm does reach.
  const float r = d_w > soft_start ? soft_reach(d_w, soft_start, reach.max) : reach.min;
  const float h = c.norm();
  const Vec3 to_target = t - S;
  const float d_t = to_target.norm();
  const Vec3 p_dir = normalized_or(p - S, fallback_direction);
  if (h <= kTinyLength) {
    return {S + r * p_dir, R, d_w > soft_start};
  }
  const Vec3 c_dir = wrist_to_tip / h;
  const Vec3 u = normalized_or(to_target, p_dir);
  if (d_t >= r + h) {
    // Out of reach even with the hand in line: the arm points along the shoulder→target ray.
    return {S + r * u, rotation_between(c_dir, u) * R, true};
  }
  if (d_t > std::abs(r - h)) {
    // The circle of wrists at distance r from S and h from t; the point nearest p keeps the
    // hand's orientation as close as possible, and the hand turns so the fingertip lands.
    const float x = (r * r - h * h + d_t * d_t) / (2.0f * d_t);
    const float rho = std::sqrt(std::max(0.0f, r * r - x * x));
    const Vec3 q = p - S;
    const Vec3 n = normalized_or(q - q.dot(u) * u, any_perpendicular(u));
    const Vec3 W = S + x * u + rho * n;
    return {W, rotation_between(c_dir, normalized_or(t - W, c_dir)) * R, false};
  }
  // The target is nearer the shoulder than the folded arm and finger allow: the wrist as near as
  // it gets, the finger toward the target.
  const Vec3 W = S + r * p_dir;
  return {W, rotation_between(c_dir, normalized_or(t - W, c_dir)) * R, false};
}

// A fingertip target beyond `tip_reach` from shoulder S, brought in along the ray from the eyes E
// through it to the farthest point the fingertip reaches (the ray–sphere intersection), so the
// eye–fingertip ray is unchanged. Targets within reach, and eyes outside the sphere (no such
// point in front of them), are left as they are.
Vec3 along_sight(const Vec3& S, const Vec3& E, const Vec3& t, float tip_reach) {
  if (!E.allFinite() || (t - S).norm() <= tip_reach || (E - S).norm() >= tip_reach) {
    return t;
  }
  const Vec3 u = normalized_or(t - E, Vec3::Zero());
  if (u.isZero()) {
    return t;
  }
  // |E + s·u − S| = tip_reach, s > 0: s² + 2·s·(u·m) + |m|² − R² = 0 with m = E − S.
  const Vec3 m = E - S;
  const float b = u.dot(m);
  const float c = m.squaredNorm() - tip_reach * tip_reach;  // < 0: E is inside the sphere
  const float s = -b + std::sqrt(std::max(0.0f, b * b - c));
  return E + s * u;
}

}  // namespace

bool DeicticArmJob::validate(std::string_view* reason) const {
  if (skeleton == nullptr || arm == nullptr || limits == nullptr) {
    return fail(reason, "skeleton, arm and limits must be set");
  }
  const auto n = static_cast<std::size_t>(skeleton->joint_count());
  if (local.size() != n || model.size() != n) {
    return fail(reason, "local and model must hold one pose per skeleton joint");
  }
  const ArmRig& a = *arm;
  if (!valid_joint(*skeleton, a.upper) || !valid_joint(*skeleton, a.lower) ||
      !valid_joint(*skeleton, a.hand) || a.upper == a.lower || a.lower == a.hand ||
      !is_ancestor(*skeleton, a.upper, a.lower) || !is_ancestor(*skeleton, a.lower, a.hand)) {
    return fail(reason, "arm: upper, lower and hand must be joints, each below the previous");
  }
  if (a.index_count < 0 || a.index_count > 3) {
    return fail(reason, "arm: index_count must lie in 0..3");
  }
  for (int k = 0; k < a.index_count; ++k) {
    const int parent = k == 0 ? a.hand : a.index[k - 1];
    if (!valid_joint(*skeleton, a.index[k]) || a.index[k] == parent ||
        !is_ancestor(*skeleton, parent, a.index[k]) ||
        (k > 0 && skeleton->parents[a.index[k]] != parent)) {
      return fail(reason,
                  "arm: index joints must hang below the hand, each the parent of the next");
    }
  }
  if (!(soften > 0.0f && soften <= 1.0f)) {
    return fail(reason, "soften is not in (0, 1]");
  }
  if (!check(*limits).empty()) {
    return fail(reason, "limits are not usable (see check(IkLimits))");
  }
  return true;
}

bool DeicticArmJob::run() const {
  if (!validate()) {
    return false;
  }
  const ArmRig& a = *arm;
  const int tip_joint = a.tip_joint();
  update_model_path(*skeleton, local, model, a.upper, tip_joint);
  const auto tip_now = [&] { return transform_point(model[tip_joint], a.tip_offset); };
  DeicticArmResult out;
  if (!fingertip.allFinite() || !is_finite(model[a.upper])) {
    if (result != nullptr) {
      *result = out;
    }
    return true;  // nothing to reach: the arm keeps its pose
  }

  // The arm's input pose: every placement round starts from it, so the two-bone job always
  // sees the elbow hinge where the rig has it (the wrist job twists the forearm about it).
  const std::array<int, 3> joints = {a.upper, a.lower, a.hand};
  std::array<Mat3, 3> input{};
  for (std::size_t k = 0; k < joints.size(); ++k) {
    input[k] = local[joints[k]].rotation;
  }
  const Vec3 S = model[a.upper].translation;
  const Pose& hand0 = model[a.hand];
  const Vec3 c = hand0.rotation.transpose() * (tip_now() - hand0.translation);
  const float upper_length = (model[a.lower].translation - S).norm();
  const float lower_length = (hand0.translation - model[a.lower].translation).norm();
  const Reach reach = reach_of(upper_length, lower_length, limits->elbow);
  const float soft_start = std::max(soften * reach.max, reach.min);
  const Vec3 pole_m = pole.allFinite() && pole.norm() > kTinyLength ? pole : a.pole;
  const Vec3 rest_direction = normalized_or(hand0.translation - S, Vec3(0, -1, 0));

  Mat3 wanted = wrist_rotation.allFinite()
                    ? Mat3(orthonormalized(wrist_rotation) * a.R_hand_wrist.transpose())
                    : hand0.rotation;
  const Mat3 wanted_input = wanted;
  // Places wrist and hand for a fingertip target, in rounds (the wrist's limits may change the
  // orientation the placement assumed). Every round starts from the input pose.
  const auto place_for = [&](const Vec3& target) {
    wanted = wanted_input;
    for (int round = 0; round < kPlacementRounds; ++round) {
      for (std::size_t k = 0; k < joints.size(); ++k) {
        local[joints[k]].rotation = input[k];
      }
      update_model_path(*skeleton, local, model, a.upper, a.hand);
      const Placement place = place_wrist(S, target, wanted, c, reach, soft_start, rest_direction);
      out.beyond_reach = place.beyond_reach;

      bend_arm_and_turn_hand(*skeleton, a, *limits, place.wrist, pole_m, place.hand, local, model);
      const Mat3& achieved = model[a.hand].rotation;
      if (rotation_angle(achieved * place.hand.transpose()) < 1e-4f) {
        break;
      }
      wanted = achieved;  // place the wrist again for the orientation the limits allow
    }
  };
  // The index finger bends the rest of the way to the fingertip target.
  std::array<Mat3, 3> index_input{};
  for (int k = 0; k < a.index_count; ++k) {
    index_input[static_cast<std::size_t>(k)] = local[a.index[static_cast<std::size_t>(k)]].rotation;
  }
  const auto bend_finger = [&](const Vec3& target) {
    update_model_path(*skeleton, local, model, a.hand, tip_joint);
    if (a.index_count == 0) {
      return;
    }
    IndexFingerJob finger;
    finger.skeleton = skeleton;
    finger.chain = std::span<const int>(a.index.data(), static_cast<std::size_t>(a.index_count));
    finger.flexion_axes =
        std::span<const Vec3>(a.index_axes.data(), static_cast<std::size_t>(a.index_count));
    finger.flexion =
        std::span<const HingeRange>(limits->index.data(), static_cast<std::size_t>(a.index_count));
    finger.tip_offset = a.tip_offset;
    finger.target = target;
    finger.local = local;
    finger.model = model;
    finger.run();
  };
  place_for(fingertip);
  bend_finger(fingertip);
  // Beyond reach, pointing keeps the eye–fingertip ray (with sight_origin): place again for the
  // point of the sight ray the fingertip reaches with the hand in line (the softened wrist reach
  // plus the hand), from the input pose.
  if (out.beyond_reach && (tip_now() - fingertip).norm() >= 1e-3f) {
    const Vec3 target = along_sight(S, sight_origin, fingertip, soft_start + c.norm());
    if (target != fingertip) {
      for (int k = 0; k < a.index_count; ++k) {
        local[a.index[static_cast<std::size_t>(k)]].rotation =
            index_input[static_cast<std::size_t>(k)];
      }
      place_for(target);
      bend_finger(target);
      out.beyond_reach = true;
    }
  }
  out.tip_error = (tip_now() - fingertip).norm();
  out.reached = out.tip_error < 1e-3f;
  if (result != nullptr) {
    *result = out;
  }
  return true;
}

}  // namespace deixis::ik
