#include "ik/avatar_solver.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "ik/eye_job.h"
#include "ik/job_validation.h"
#include "ik/lean_job.h"
#include "ik/rotations.h"
#include "ik/spine_aim_job.h"

namespace deixis::ik {
namespace {

// Targets farther than this from the root (m) are brought in along their direction, so every
// distance the jobs compute stays finite (a point 10^30 m away would overflow a squared norm).
constexpr float kFarAway = 1e4f;

Vec3 brought_in(const Vec3& p) {
  const float m = p.cwiseAbs().maxCoeff();
  if (!std::isfinite(m) || m <= kFarAway / 2) {
    return p;  // non-finite targets are the jobs' to refuse
  }
  const Vec3 direction = (p / m).normalized();
  return m * (p / m).norm() > kFarAway ? Vec3(kFarAway * direction) : p;
}

std::string bone_text(Bone bone) {
  return "'" + std::string(bone_name(bone)) + "'";
}

void check_bones(const HumanoidRig& rig) {
  for (int b = 0; b < kBoneCount; ++b) {
    const Bone bone = static_cast<Bone>(b);
    const int j = rig.joint[b];
    if (j >= rig.skeleton.joint_count() || j < -1) {
      throw Error("avatar rig: bone " + bone_text(bone) + " maps to joint " + std::to_string(j) +
                  ", not a joint of the skeleton");
    }
    if (j == -1 && is_required(bone)) {
      throw Error("avatar rig: required bone " + bone_text(bone) + " is missing");
    }
  }
}

// Appends `bone` to a chain when the rig has it, checking the chain stays ancestor-ordered.
template <std::size_t N>
void append(const HumanoidRig& rig, Bone bone, std::array<int, N>& chain, int& count) {
  const int j = rig[bone];
  if (j < 0) {
    return;
  }
  if (count > 0 && !is_ancestor(rig.skeleton, chain[count - 1], j)) {
    throw Error("avatar rig: bone " + bone_text(bone) + " is not below the spine bone before it");
  }
  chain[count++] = j;
}

ChestCylinder make_cylinder(const AvatarSolver& s, int chest) {
  const Pose& T_model_chest = s.rest_model[chest];
  const Vec3 left = s.rest_model[s.arms[index(Hand::kLeft)].upper].translation;
  const Vec3 right = s.rest_model[s.arms[index(Hand::kRight)].upper].translation;
  const float span = (right - left).norm();
  const float margin = s.config.cylinder_margin;
  // Upright in the rest pose, centred between the shoulders at the chest's height, from the
  // hips to the shoulders. Torso proportions: chest width ≈ 0.8, depth ≈ 0.6 of shoulder span.
  const Vec3 centre(0.5f * (left.x() + right.x()), T_model_chest.translation.y(),
                    0.5f * (left.z() + right.z()));
  ChestCylinder c;
  c.T_chest_cylinder = compose(inverse(T_model_chest), Pose{Mat3::Identity(), centre});
  c.half_width = 0.4f * span + margin;
  c.half_depth = 0.3f * span + margin;
  c.bottom = s.rest_model[s.rig[Bone::kHips]].translation.y() - centre.y();
  c.top = 0.5f * (left.y() + right.y()) - centre.y();
  if (!(c.half_width > margin && c.bottom < c.top)) {
    throw Error("avatar rig: the shoulders are not apart and above the hips in the rest pose");
  }
  // The non-deictic arm's last resort points straight out from the shoulder, out of the chest.
  for (const Vec3& shoulder : {left, right}) {
    const Vec3 q = transform_point(inverse(c.T_chest_cylinder),
                                   transform_point(inverse(T_model_chest), shoulder));
    if (std::abs(q.x()) <= c.half_width) {
      throw Error("IK config: cylinder_margin puts the shoulders inside the chest cylinder");
    }
  }
  return c;
}

// H, the eye midpoint, where the head joint's model pose puts it.
Vec3 eye_midpoint(const AvatarSolver& s, std::span<const Pose> model) {
  return transform_point(model[s.rig[Bone::kHead]], s.rig.eye_midpoint_in_head);
}

// Turns the aim chain from its joint `first` up to the head towards `head_target` (SpineAimJob).
void aim_head(const AvatarSolver& s, const Mat3& head_target, int first, std::span<Pose> local,
              std::span<Pose> model, bool& reached) {
  SpineAimJob job;
  job.skeleton = &s.rig.skeleton;
  const auto count = static_cast<std::size_t>(s.aim_count - first);
  job.chain = std::span<const int>(s.aim_chain.data() + first, count);
  job.weights = std::span<const float>(s.aim_shares.data() + first, count);
  job.max_angles = std::span<const float>(s.aim_limits.data() + first, count);
  job.target = head_target;
  job.local = local;
  job.model = model;
  job.reached = &reached;
  job.run();
}

// Bends spine, chest and neck so that the head joint goes to `head_joint_target` (LeanJob).
void lean_head(const AvatarSolver& s, const Vec3& head_joint_target, std::span<Pose> local,
               std::span<Pose> model) {
  LeanJob lean;
  lean.skeleton = &s.rig.skeleton;
  const auto count = static_cast<std::size_t>(s.lean_count);
  lean.chain = std::span<const int>(s.lean_chain.data(), count);
  lean.weights = std::span<const float>(s.lean_shares.data(), count);
  lean.max_angles = std::span<const float>(s.lean_limits.data(), count);
  lean.end_joint = s.rig[Bone::kHead];
  lean.target = head_joint_target;
  lean.local = local;
  lean.model = model;
  lean.run();
}

// Steps 2–3: the head's orientation and position, H's target pose T_model_H in the model frame.
// At rest the frame H has the model's axes, so the head joint's wanted rotation is
// R_model_H · R_model_head(rest).
void solve_head(const AvatarSolver& s, const Pose& T_model_H, std::span<Pose> local,
                std::span<Pose> model, bool& reached) {
  const Skeleton& skeleton = s.rig.skeleton;
  const int head = s.rig[Bone::kHead];
  const Mat3 head_target = T_model_H.rotation * s.rest_model[head].rotation;
  aim_head(s, head_target, 0, local, model, reached);
  // Leaning places the head joint where H lands once the head has its target orientation.
  const Mat3 R_head_final =
      head_target.allFinite() ? orthonormalized(head_target) : model[head].rotation;
  const Vec3 head_joint_target = T_model_H.translation - R_head_final * s.rig.eye_midpoint_in_head;
  lean_head(s, head_joint_target, local, model);
  // The head's own turn does not move the head joint, so it restores the orientation without
  // undoing the lean; only when its limit stops it do the joints below help again.
  aim_head(s, head_target, s.aim_count - 1, local, model, reached);
  if (!reached) {
    aim_head(s, head_target, s.neck_offset, local, model, reached);
  }
  if (!reached) {
    aim_head(s, head_target, 0, local, model, reached);
  }
  if (!reached) {
    // The lean used up what the orientation needs: the orientation comes first.
    for (int k = 0; k < s.aim_count; ++k) {
      local[s.aim_chain[k]] = skeleton.rest_local[s.aim_chain[k]];
    }
    update_model_path(skeleton, local, model, s.aim_chain[0], head);
    aim_head(s, head_target, 0, local, model, reached);
  }
}

// The jobs after the head need their joints' ancestors current: the paths from the spine to the
// arms and from the head to the eyes (cheaper than the whole skeleton on rigs with many fingers).
void update_limb_paths(const AvatarSolver& s, std::span<const Pose> local, std::span<Pose> model) {
  const Skeleton& skeleton = s.rig.skeleton;
  for (const ArmRig& a : s.arms) {
    update_model_path(skeleton, local, model, s.aim_chain[0], skeleton.parents[a.upper]);
  }
  for (int e = 0; e < s.eye_count; ++e) {
    update_model_path(skeleton, local, model, s.rig[Bone::kHead], skeleton.parents[s.eyes[e]]);
  }
}

// Step 4: the eyes along `gaze`, a direction in the model frame (EyeJob); a rig may have none.
void solve_eyes(const AvatarSolver& s, const Vec3& gaze, std::span<Pose> local,
                std::span<Pose> model, bool& reached) {
  if (s.eye_count == 0) {
    return;
  }
  EyeJob eyes;
  eyes.skeleton = &s.rig.skeleton;
  eyes.rest_model = s.rest_model;
  eyes.head = s.rig[Bone::kHead];
  eyes.eyes = std::span<const int>(s.eyes.data(), static_cast<std::size_t>(s.eye_count));
  eyes.gaze = gaze;
  eyes.range = s.config.limits.eyes;
  eyes.local = local;
  eyes.model = model;
  eyes.reached = &reached;
  eyes.run();
}

// Step 5: the deictic arm towards the world-frame end-effectors `ee` (DeicticArmJob).
void solve_deictic_arm(const AvatarSolver& s, Hand hand, const Pose& T_root_world,
                       const EndEffectorPoses& ee, std::span<Pose> local, std::span<Pose> model,
                       DeicticArmResult& result) {
  const ArmRig& arm_rig = s.arms[index(hand)];
  DeicticArmJob job;
  job.skeleton = &s.rig.skeleton;
  job.arm = &arm_rig;
  job.limits = &s.config.limits;
  job.pole = arm_rig.pole;
  job.soften = s.config.soften;
  job.wrist_rotation = T_root_world.rotation * ee.T_world_wrist.rotation;
  job.fingertip = brought_in(transform_point(T_root_world, ee.index_tip));
  // Beyond reach, keep the ray from the avatar's own eyes (after the lean) through the fingertip.
  job.sight_origin = eye_midpoint(s, model);
  job.local = local;
  job.model = model;
  job.result = &result;
  job.run();
}

// Step 6: the other arm, placed from the avatar's own H after leaning (OtherArmJob).
void solve_other_arm(const AvatarSolver& s, Hand hand, const OtherHandTarget& target,
                     std::span<Pose> local, std::span<Pose> model, OtherArmResult& result) {
  const ArmRig& arm_rig = s.arms[index(hand)];
  OtherArmJob job;
  job.skeleton = &s.rig.skeleton;
  job.arm = &arm_rig;
  job.limits = &s.config.limits;
  job.cylinder = &s.cylinder;
  job.chest = s.cylinder_joint;
  job.head_position = eye_midpoint(s, model);
  job.target = target;
  job.target.distance = std::min(job.target.distance, kFarAway);
  job.pole = arm_rig.pole;
  job.soften = s.config.soften;
  job.local = local;
  job.model = model;
  job.result = &result;
  job.run();
}

}  // namespace

AvatarSolver AvatarSolver::build(const HumanoidRig& rig, const AvatarSolverConfig& config) {
  validate(rig.skeleton, "avatar rig");
  check_bones(rig);
  if (const std::string_view why = check(config.limits); !why.empty()) {
    throw Error("IK limits: " + std::string(why));
  }
  const auto share_ok = [](float w) { return w >= 0.0f && w <= 1.0f; };
  if (!share_ok(config.spine_share) || !share_ok(config.chest_share) ||
      !share_ok(config.neck_share) || !share_ok(config.lean_spine_share)) {
    throw Error("IK config: spine, chest, neck and lean shares must lie in [0, 1]");
  }
  if (!(config.soften > 0.0f && config.soften <= 1.0f) || !(config.cylinder_margin >= 0.0f)) {
    throw Error("IK config: soften must lie in (0, 1] and cylinder_margin be ≥ 0");
  }
  if (!rig.eye_midpoint_in_head.allFinite()) {
    throw Error("avatar rig: the eye midpoint is not finite");
  }

  AvatarSolver s;
  s.rig = rig;
  s.config = config;
  s.rest_model = rest_model_poses(rig.skeleton);
  s.eye_midpoint_rest = transform_point(s.rest_model[rig[Bone::kHead]], rig.eye_midpoint_in_head);

  const IkLimits& l = config.limits;
  append(rig, Bone::kSpine, s.aim_chain, s.aim_count);
  s.aim_shares[0] = config.spine_share;
  s.aim_limits[0] = l.spine;
  if (rig[Bone::kChest] >= 0) {
    s.aim_shares[s.aim_count] = config.chest_share;
    s.aim_limits[s.aim_count] = l.chest;
    append(rig, Bone::kChest, s.aim_chain, s.aim_count);
  }
  s.neck_offset = s.aim_count;
  if (rig[Bone::kNeck] >= 0) {
    s.aim_shares[s.aim_count] = config.neck_share;
    s.aim_limits[s.aim_count] = l.neck;
    append(rig, Bone::kNeck, s.aim_chain, s.aim_count);
  }
  s.aim_shares[s.aim_count] = 1.0f;
  s.aim_limits[s.aim_count] = l.head;
  append(rig, Bone::kHead, s.aim_chain, s.aim_count);

  // The lean pivots are the aim chain below the head: spine, chest, neck (the hips stay: the legs
  // stand). The neck is one because people shift the head with it.
  s.lean_count = s.aim_count - 1;
  for (int k = 0; k < s.lean_count; ++k) {
    s.lean_chain[k] = s.aim_chain[k];
    s.lean_limits[k] = s.aim_limits[k];
    s.lean_shares[k] = k == 0 && s.lean_count > 1 ? config.lean_spine_share : 1.0f;
  }

  for (const Bone eye : {Bone::kLeftEye, Bone::kRightEye}) {
    const int j = rig[eye];
    if (j >= 0) {
      if (j == rig[Bone::kHead] || !is_ancestor(rig.skeleton, rig[Bone::kHead], j)) {
        throw Error("avatar rig: bone " + bone_text(eye) + " is not below 'head'");
      }
      s.eyes[s.eye_count++] = j;
    }
  }
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    s.arms[index(h)] = make_arm_rig(rig, s.rest_model, h, l);
  }
  s.cylinder_joint = rig[Bone::kChest] >= 0 ? rig[Bone::kChest] : rig[Bone::kSpine];
  s.cylinder = make_cylinder(s, s.cylinder_joint);
  return s;
}

Pose T_world_root_from_origin(const AvatarSolver& solver, const Pose& T_world_origin) {
  return compose(T_world_origin, Pose{Mat3::Identity(), -solver.eye_midpoint_rest});
}

bool AvatarSolveJob::validate(std::string_view* reason) const {
  if (solver == nullptr || targets == nullptr) {
    return fail(reason, "solver and targets must be set");
  }
  const auto n = static_cast<std::size_t>(solver->joint_count());
  if (local.size() != n || model.size() != n) {
    return fail(reason, "local and model must hold one pose per skeleton joint");
  }
  if (!is_finite(T_world_root) ||
      !((T_world_root.rotation.transpose() * T_world_root.rotation - Mat3::Identity())
            .cwiseAbs()
            .maxCoeff() < 1e-3f) ||
      !(T_world_root.rotation.determinant() > 0.0f)) {
    return fail(reason, "T_world_root must be finite with a rotation matrix");
  }
  return true;
}

bool AvatarSolveJob::run() const {
  if (!validate()) {
    return false;
  }
  const AvatarSolver& s = *solver;
  const Pose T_root_world = inverse(T_world_root);
  const EndEffectorPoses& ee = targets->deictic;
  AvatarSolveReport out;

  // 1. Rest.
  std::copy(s.rig.skeleton.rest_local.begin(), s.rig.skeleton.rest_local.end(), local.begin());
  std::copy(s.rest_model.begin(), s.rest_model.end(), model.begin());

  // 2–3. Head orientation and position, then the paths the eyes and arms hang from.
  Pose T_model_H = compose(T_root_world, ee.T_world_head);
  T_model_H.translation = brought_in(T_model_H.translation);
  solve_head(s, T_model_H, local, model, out.head_reached);
  update_limb_paths(s, local, model);
  if (T_model_H.translation.allFinite()) {
    out.head_position_error = (eye_midpoint(s, model) - T_model_H.translation).norm();
  }

  // 4–6. Eyes, the deictic arm, the other arm.
  solve_eyes(s, T_root_world.rotation * ee.gaze, local, model, out.eyes_reached);
  const Hand deictic = targets->deictic_hand;
  solve_deictic_arm(s, deictic, T_root_world, ee, local, model, out.deictic);
  solve_other_arm(s, other(deictic), targets->other, local, model, out.other);

  // 7. Every joint's model pose (the jobs updated only their own paths).
  local_to_model(s.rig.skeleton, local, model);
  if (report != nullptr) {
    *report = out;
  }
  return true;
}

}  // namespace deixis::ik
