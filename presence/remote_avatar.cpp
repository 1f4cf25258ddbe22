#include "presence/remote_avatar.h"

#include <algorithm>
#include <utility>

#include "ik/other_arm_job.h"
#include "presence/body_turn.h"
#include "presence/gaze_settle.h"
#include "presence/pointing_settle.h"
#include "presence/touch_contact.h"

namespace deixis::presence {
namespace {

constexpr float kTickSeconds = 1.0f / 30.0f;  // the translation's rate (docs/conventions.md)

TranslatorConfig translator_config(const ik::AvatarSolver& solver,
                                   const RemoteAvatarConfig& config) {
  TranslatorConfig t;
  t.user = config.user;
  t.T_world_avatar_root = avatar_origin(solver, config.T_world_floor);
  t.avatar_height = solver.rig.height;
  t.noise_seed = config.noise_seed;
  t.mirrored = config.mirrored;
  return t;
}

}  // namespace

Pose avatar_origin(const ik::AvatarSolver& solver, const Pose& T_world_floor) {
  // The rig's model frame stands on the floor (y = 0 at the soles), so H's rest height above the
  // floor is its model y; O keeps only the placement's yaw (paper §IV.A).
  const Vec3 h = solver.eye_midpoint_rest;
  return compose(T_world_floor, Pose{Mat3::Identity(), Vec3(h.x(), h.y(), h.z())});
}

RemoteAvatar::RemoteAvatar(nn::Mpnet mpnet, nn::Ugnet ugnet, const ik::AvatarSolver& solver,
                           const RemoteAvatarConfig& config)
    : solver_(&solver),
      translator_(std::move(mpnet), std::move(ugnet), translator_config(solver, config)),
      T_world_floor_(config.T_world_floor),
      T_world_model_(
          ik::T_world_root_from_origin(solver, translator_.config().T_world_avatar_root)),
      touch_contact_(config.touch_contact),
      gaze_settle_(config.gaze_settle),
      pointing_settle_(config.pointing_settle),
      body_turn_(config.body_turn),
      local_(solver.rig.skeleton.rest_local),
      model_(solver.rest_model) {}

bool RemoteAvatar::tick(const TrackingFrame* frame, const LocalTargets& room) {
  if (begin_tick(frame, room)) {
    translator_.run_networks();
  }
  return finish_tick(room);
}

bool RemoteAvatar::begin_tick(const TrackingFrame* frame, const LocalTargets& room) {
  if (body_turn_) {
    turn_body(room);
  }
  return translator_.begin_tick(frame, room);
}

void RemoteAvatar::settle_pointing(const LocalTargets& room) {
  // About the eyes where IK put them last tick, not the networks' H: the watcher's eye →
  // fingertip ray starts at the avatar's eyes, IK places them a little off H (low targets: up to
  // 2–3° of the ray's direction), and during a hold they hardly move from one tick to the next.
  // Before touch contact, which then measures the settled fingertip against the object's surface.
  const Vec3 eyes = eye_midpoint();
  const Mat3 R = pointing_settle_rotation(
      frame_.deictic.index_tip, eyes, room.find_position(frame_.hand_target),
      frame_.person_point_off_deg, frame_.progression[1], frame_.hand_weight);
  Pose& wrist = targets_.deictic.T_world_wrist;
  wrist.rotation = R * wrist.rotation;
  wrist.translation = eyes + R * (wrist.translation - eyes);
  targets_.deictic.index_tip = eyes + R * (targets_.deictic.index_tip - eyes);
}

void RemoteAvatar::turn_body(const LocalTargets& room) {
  // Last tick's designation (this tick's progression is known only once the networks have run).
  const TurnDesignation d = turn_designation(
      room.find_position(frame_.hand_target), frame_.hand_target, frame_.progression[1],
      room.find_position(frame_.head_target), frame_.head_target, frame_.progression[0]);
  const float weight = frame_.ready ? d.weight : 0.0f;
  const float wanted =
      wanted_turn(avatar_origin(*solver_, T_world_floor_), d.target, weight, d.pointing);
  const float next = turned(turn_, wanted, kTickSeconds);
  if (next == turn_) {
    return;
  }
  turn_ = next;
  const Pose T_world_turned = compose(T_world_floor_, Pose{yaw_rotation(turn_), Vec3::Zero()});
  translator_.set_avatar_root(avatar_origin(*solver_, T_world_turned));
  T_world_model_ = ik::T_world_root_from_origin(*solver_, translator_.config().T_world_avatar_root);
}

bool RemoteAvatar::finish_tick(const LocalTargets& room) {
  frame_ = translator_.tick_result();
  if (!frame_.ready) {
    return false;
  }
  targets_.deictic_hand = frame_.deictic_hand;
  targets_.deictic = frame_.deictic;
  if (pointing_settle_) {
    settle_pointing(room);
  }
  if (touch_contact_) {
    const TargetObject* object = room.map != nullptr ? room.map->find(frame_.hand_target) : nullptr;
    const Vec3 offset = touch_contact_offset(
        targets_.deictic.index_tip, object, frame_.progression[1], frame_.hand_weight,
        TouchContactConfig{}.radius * solver_->rig.height / 1.70f);
    targets_.deictic.index_tip += offset;
    targets_.deictic.T_world_wrist.translation += offset;
  }
  if (gaze_settle_) {
    targets_.deictic.gaze = settled_gaze(
        frame_.deictic.gaze, frame_.deictic.T_world_head.translation,
        room.find_position(frame_.head_target), frame_.person_gaze_off_deg, frame_.head_weight);
  }
  targets_.other = ik::other_hand_target(frame_.other_wrist_from_head);

  ik::AvatarSolveJob job;
  job.solver = solver_;
  job.T_world_root = T_world_model_;
  job.targets = &targets_;
  job.local = local_;
  job.model = model_;
  job.report = &report_;
  // The job only refuses inputs the translator never produces (it guarantees finite poses); if
  // it ever did, the avatar would keep last tick's pose rather than show garbage.
  job.run();
  return true;
}

Vec3 RemoteAvatar::eye_midpoint() const {
  const int head = solver_->rig[ik::Bone::kHead];
  const Pose T_world_head = compose(T_world_model_, model_[static_cast<std::size_t>(head)]);
  return T_world_head.rotation * solver_->rig.eye_midpoint_in_head + T_world_head.translation;
}

Vec3 RemoteAvatar::eye_line_of_sight() const {
  if (solver_->eye_count == 0) {
    return gaze();
  }
  // The eye job turns each eye from its rest so that the rest pose's forward (−Z) becomes the
  // line of sight (ik/eye_job.cpp); both eyes look along parallel lines.
  const auto eye = static_cast<std::size_t>(solver_->eyes[0]);
  const Mat3 R_model_sight = model_[eye].rotation * solver_->rest_model[eye].rotation.transpose();
  return T_world_model_.rotation * R_model_sight * Vec3(0, 0, -1);
}

Vec3 RemoteAvatar::index_fingertip() const {
  const ik::ArmRig& arm = solver_->arms[index(frame_.deictic_hand)];
  const Pose T_world_tip =
      compose(T_world_model_, model_[static_cast<std::size_t>(arm.tip_joint())]);
  return T_world_tip.rotation * arm.tip_offset + T_world_tip.translation;
}

}  // namespace deixis::presence
