#include "ik/other_arm_job.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ik/job_validation.h"
#include "ik/rotations.h"
#include "ik/two_bone_job.h"  // reach_of, soft_reach

namespace deixis::ik {
namespace {

// Rounds of "within reach, then out of the chest" for the wrist's goal.
constexpr int kRounds = 8;
constexpr int kBisections = 16;  // the last resort's turn, to 1/65536 of its angle

bool finite(const OtherHandTarget& t) {
  return std::isfinite(t.azimuth) && std::isfinite(t.elevation) && std::isfinite(t.distance) &&
         t.R_root_wrist.allFinite();
}

}  // namespace

Vec3 direction_of(float azimuth, float elevation) {
  const float c = std::cos(elevation);
  return {-std::sin(azimuth) * c, std::sin(elevation), -std::cos(azimuth) * c};
}

OtherHandTarget other_hand_target(const Pose& T_world_root, const Pose& T_world_head,
                                  const Pose& T_world_wrist, float scale) {
  // Products with the transpose, not a transposed copy: GCC 12 at -O1 (the ASan build) reports a
  // false -Wmaybe-uninitialized inside Eigen's aliasing check for the copy.
  const Mat3& R_world_root = T_world_root.rotation;
  const Vec3 v = R_world_root.transpose() * (T_world_wrist.translation - T_world_head.translation);
  return other_hand_target(
      Pose{R_world_root.transpose() * T_world_wrist.rotation, scale > 0.0f ? Vec3(v / scale) : v});
}

OtherHandTarget other_hand_target(const Pose& wrist_from_head) {
  const Vec3& v = wrist_from_head.translation;
  OtherHandTarget t;
  t.azimuth = std::atan2(-v.x(), -v.z());
  t.elevation = std::atan2(v.y(), std::hypot(v.x(), v.z()));
  t.distance = v.norm();
  t.R_root_wrist = wrist_from_head.rotation;
  return t;
}

bool OtherArmJob::validate(std::string_view* reason) const {
  if (skeleton == nullptr || arm == nullptr || limits == nullptr || cylinder == nullptr) {
    return fail(reason, "skeleton, arm, limits and cylinder must be set");
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
  if (a.index_count < 0 || a.index_count > 3 ||
      (a.index_count > 0 && !is_ancestor(*skeleton, a.hand, a.tip_joint()))) {
    return fail(reason, "arm: index joints must hang below the hand");
  }
  if (!valid_joint(*skeleton, chest)) {
    return fail(reason, "chest is not a joint of the skeleton");
  }
  if (!(cylinder->half_width > 0.0f && cylinder->half_depth > 0.0f &&
        cylinder->bottom < cylinder->top && is_finite(cylinder->T_chest_cylinder))) {
    return fail(reason, "cylinder needs positive semi-axes, bottom < top and a finite frame");
  }
  if (!(soften > 0.0f && soften <= 1.0f)) {
    return fail(reason, "soften is not in (0, 1]");
  }
  if (!check(*limits).empty()) {
    return fail(reason, "limits are not usable (see check(IkLimits))");
  }
  return true;
}

bool OtherArmJob::run() const {
  if (!validate()) {
    return false;
  }
  const ArmRig& a = *arm;
  update_model_path(*skeleton, local, model, a.upper, a.tip_joint());
  OtherArmResult out;
  if (!finite(target) || !head_position.allFinite() || !is_finite(model[chest])) {
    if (result != nullptr) {
      *result = out;
    }
    return true;  // nothing to follow: the arm keeps its pose
  }
  const float side = a.side == Hand::kRight ? 1.0f : -1.0f;
  const Pose T_model_cylinder = compose(model[chest], cylinder->T_chest_cylinder);
  // inverse(T_model_cylinder), spelt out: GCC 12 at -O1 (the ASan build) warns falsely about an
  // uninitialised matrix when the inline inverse() is inlined here.
  Pose T_cylinder_model;
  T_cylinder_model.rotation.noalias() = T_model_cylinder.rotation.transpose();
  T_cylinder_model.translation.noalias() =
      -(T_model_cylinder.rotation.transpose() * T_model_cylinder.translation);
  const auto out_of_chest = [&](const Vec3& p_model, bool& moved) {
    const Vec3 q = transform_point(T_cylinder_model, p_model);
    const Vec3 q_out = project_out(*cylinder, q, side);
    moved = moved || q_out != q;
    return transform_point(T_model_cylinder, q_out);
  };
  const Vec3 wanted = head_position + std::max(target.distance, 0.0f) *
                                          direction_of(target.azimuth, target.elevation);
  const Vec3 wanted_outside = out_of_chest(wanted, out.projected);

  // The goal must be both out of the chest and within the arm's (softened) reach, or the arm,
  // falling short along the shoulder→goal line, could end inside the chest after all. Projecting
  // onto each condition in turn converges on a point that meets both; the chest comes last.
  const Vec3 S = model[a.upper].translation;
  const float upper_length = (model[a.lower].translation - S).norm();
  const float lower_length = (model[a.hand].translation - model[a.lower].translation).norm();
  const Reach reach = reach_of(upper_length, lower_length, limits->elbow);
  const float soft_start = std::max(soften * reach.max, reach.min);
  const Vec3 arm_direction = normalized_or(model[a.hand].translation - S, Vec3(0, -1, 0));
  Vec3 goal = wanted_outside;
  for (int round = 0; round < kRounds; ++round) {
    const float d = (goal - S).norm();
    const float r = std::clamp(soft_reach(d, soft_start, reach.max), reach.min, reach.max);
    if (r == d) {
      break;
    }
    goal = out_of_chest(S + r * normalized_or(goal - S, arm_direction), out.projected);
  }

  // Where the arm's wrist lands for a goal: on the shoulder→goal ray, within its reach.
  const auto landing = [&](const Vec3& g, float& distance) {
    distance = std::clamp(robust_norm(g - S), reach.min, reach.max);
    return Vec3(S + distance * normalized_or(g - S, arm_direction));
  };
  const auto inside_chest = [&](const Vec3& p_model) {
    return inside(*cylinder, transform_point(T_cylinder_model, p_model));
  };
  float distance = 0.0f;
  if (inside_chest(landing(goal, distance))) {
    // Rare: the reach and the chest leave no goal near the wanted point (a far reach across the
    // body, low down). Turn the goal's direction toward straight out from the shoulder, which
    // is always outside the chest (AvatarSolver::build checks), just as far as needed.
    const Vec3 from = normalized_or(goal - S, arm_direction);
    const Mat3 turn = rotation_between(from, T_model_cylinder.rotation * Vec3(side, 0, 0));
    float inside_at = 0.0f, outside_at = 1.0f;
    for (int i = 0; i < kBisections; ++i) {
      const float t = 0.5f * (inside_at + outside_at);
      (inside_chest(S + distance * (scale_rotation(turn, t) * from)) ? inside_at : outside_at) = t;
    }
    goal = S + distance * (scale_rotation(turn, outside_at) * from);
    out.projected = true;
  }

  const Vec3 pole_m = pole.allFinite() && pole.norm() > kTinyLength ? pole : a.pole;
  // The goal is already softened (the two-bone job itself runs without softening).
  bend_arm_and_turn_hand(*skeleton, a, *limits, goal, pole_m,
                         orthonormalized(target.R_root_wrist) * a.R_hand_wrist.transpose(), local,
                         model);
  update_model_path(*skeleton, local, model, a.hand, a.tip_joint());

  out.wrist_target = goal;
  out.reached = (model[a.hand].translation - wanted_outside).norm() < 1e-3f;
  if (result != nullptr) {
    *result = out;
  }
  return true;
}

}  // namespace deixis::ik
