#pragma once
// The remote person's avatar in this room, one tick at a time: their tracking frame and
// this room's targets go through the translator (features → MPNet → blend → UGNet → decode) and
// the whole-avatar IK, and come out as the model poses of a skinned humanoid standing where this
// site put it.
//
//   TrackingFrame ──Translator──▶ AvatarFrame (end-effectors, world) ──AvatarSolveJob──▶ poses
//
// With touch contact on, a touch that UGNet brings within a few centimetres of the object ends on
// its surface (touch_contact.h); with gaze settling on, a gaze that UGNet brings near this room's
// copy of its target ends on it (gaze_settle.h), and pointing settling does the same for the
// hand (pointing_settle.h); with body turn on, the avatar turns toward a target that stands
// behind its spot while the person designates it (body_turn.h).
//
// The avatar's root O (paper §IV.A: the eye midpoint H of its upright posture, yaw-only) is placed
// from where it stands on this room's floor and the rig's own eye height, and its size (for the
// translator's scaling) is the rig's height. Everything a tick needs is sized at construction;
// tick() allocates nothing.

#include <span>
#include <vector>

#include "gesture/translator.h"
#include "ik/avatar_solver.h"

namespace deixis::presence {

struct RemoteAvatarConfig {
  BodyCalibration user;          // the remote person, in their room (from their hello)
  Pose T_world_floor;            // where the avatar stands in this room: a floor point, yaw only
  std::uint32_t noise_seed = 1;  // for a diffusion UGNet
  bool touch_contact = true;     // finish touches on the object's surface (touch_contact.h)
  bool mirrored = false;         // the networks run on the person's mirror image (translator.h)
  bool gaze_settle = true;       // finish gazes on their target (gaze_settle.h)
  bool pointing_settle = true;   // finish points on their target (pointing_settle.h)
  bool body_turn = true;         // turn toward targets behind the spot (body_turn.h)
};

// Where the avatar's root O goes for a floor placement: H of the rig's rest pose straight above
// the floor point, with the placement's yaw.
Pose avatar_origin(const ik::AvatarSolver& solver, const Pose& T_world_floor);

class RemoteAvatar {
 public:
  // `solver` must outlive the RemoteAvatar (one solver serves every avatar wearing its rig).
  RemoteAvatar(nn::Mpnet mpnet, nn::Ugnet ugnet, const ik::AvatarSolver& solver,
               const RemoteAvatarConfig& config);

  // One 30 Hz tick. `frame` is null when no frame arrived in time. Returns false while the avatar
  // is hidden (no valid frame yet); the poses then keep the rest pose.
  bool tick(const TrackingFrame* frame, const LocalTargets& room);

  // tick() in halves for presence::tick_people, which batches many avatars' networks:
  // begin_tick() ticks the translator up to its networks and says whether they must run (then
  // the caller completes translator()'s tick, e.g. in a TranslatorBatch); finish_tick() does the
  // rest (touch contact and IK) and returns what tick() returns. tick() is exactly these with the
  // networks run alone.
  bool begin_tick(const TrackingFrame* frame, const LocalTargets& room);
  bool finish_tick(const LocalTargets& room);
  Translator& translator() { return translator_; }

  bool visible() const { return frame_.ready; }
  const AvatarFrame& frame() const { return frame_; }  // the translator's output this tick
  // The gaze (unit, world) the avatar's eyes are given this tick: the translator's, settled onto
  // its target when gaze settling applies (gaze_settle.h).
  const Vec3& gaze() const { return targets_.deictic.gaze; }
  const ik::AvatarSolveReport& report() const { return report_; }
  const TranslatorStats& stats() const { return translator_.stats(); }

  // T_model_joint and T_parent_joint of every joint of the rig, and where the model frame is.
  std::span<const Pose> model_pose() const { return model_; }
  std::span<const Pose> local_pose() const { return local_; }
  const Pose& T_world_model() const { return T_world_model_; }
  // How far the body is turned from the spot's facing (rad, + to the left; body_turn.h).
  float body_turn() const { return turn_; }
  // The avatar's root O this tick: the spot's, turned with the body (the networks' frame).
  const Pose& T_world_root() const { return translator_.config().T_world_avatar_root; }
  const ik::AvatarSolver& solver() const { return *solver_; }

  // World positions of the avatar's eye midpoint H and deictic index fingertip after IK (what
  // an observer in this room sees; the end-to-end checks measure these).
  Vec3 eye_midpoint() const;
  Vec3 index_fingertip() const;
  // The line of sight (unit, world) of the avatar's eyes after IK, clamped to their range; on a
  // rig without eye joints, the gaze they were given (gaze()).
  Vec3 eye_line_of_sight() const;

 private:
  // Turns the body for this tick from last tick's designation (body_turn.h).
  void turn_body(const LocalTargets& room);
  void settle_pointing(const LocalTargets& room);  // pointing_settle.h, on targets_

  const ik::AvatarSolver* solver_;
  Translator translator_;
  Pose T_world_floor_;  // the spot: where the site placed the avatar
  float turn_ = 0.0f;   // the body's turn from the spot's facing (rad)
  Pose T_world_model_;
  bool touch_contact_;
  bool gaze_settle_;
  bool pointing_settle_;
  bool body_turn_;
  AvatarFrame frame_;
  ik::AvatarTargets targets_;
  ik::AvatarSolveReport report_;
  std::vector<Pose> local_;
  std::vector<Pose> model_;
};

}  // namespace deixis::presence
