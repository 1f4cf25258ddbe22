#pragma once
// The translator of one remote person (docs/conventions.md#translator): every tick it takes that
// person's tracking frame (from their room) and this room's targets, and returns where the person's
// avatar in *this* room has its head, eyes, deictic hand and index fingertip, so that it looks,
// points and touches at this room's copies of the objects while free-form gestures pass through.
//
//   tracking frame ──features.h──▶ MPNet row, user x ─┐
//   this room's target positions ──▶ avatar target ───┴─▶ TranslationLoop ─▶ avatar x
//   avatar x ──decode_end_effectors──▶ world poses for IK
//
// Missed tracking (no frame, a part flagged invalid, NaN or Inf anywhere) holds the last valid
// frame and is counted; nothing non-finite ever reaches the output. Per-person state is fixed
// size (TranslationLoop::kStateBytes plus the held frame); tick() never allocates.

#include <cstdint>
#include <random>
#include <span>

#include "core/target_map.h"
#include "gesture/translation_loop.h"

namespace deixis {

struct TranslatorConfig {
  BodyCalibration user;      // the remote person, in their room (from their hello)
  Pose T_world_avatar_root;  // where their avatar stands in this room: its root O, yaw-only
  float avatar_height = 1.70f;
  std::uint32_t noise_seed = 1;  // for a diffusion UGNet's draws
  // Run the networks on the person's mirror image (docs/conventions.md#left-hand-mirroring):
  // their x and both θ mirrored on the way in, the avatar's x mirrored back on the way out, so
  // that a left-handed person goes through the right-hand weights (docs/decisions.md §68).
  bool mirrored = false;
};

// What this room knows about targets: its target map, where the local user's head is (the
// "other person" target, id 0, of a direct two-site session) and, in a room of several people,
// every person's head by PersonId (person_target(id); the own user under their own id). A
// person target not in `people` counts as an unknown target.
struct LocalTargets {
  const TargetMap* map = nullptr;
  Vec3 partner_head = Vec3::Zero();
  std::span<const PersonTarget> people{};

  const PersonTarget* find_person(PersonId id) const { return deixis::find_person(people, id); }
  // Where target `id` stands in this room: an object of the map, the other person of a direct
  // session, a person of the room; null when this room has no copy of it.
  const Vec3* find_position(TargetId id) const;
};

struct AvatarFrame {
  bool ready = false;  // false until the first valid frame: the avatar is not shown
  bool held = false;   // this tick reused the last valid frame (missed tracking)
  Hand deictic_hand = Hand::kRight;
  EndEffectorPoses deictic;  // head, gaze, deictic wrist and index fingertip, this room's world
  // The non-deictic wrist relative to the head H, in the user's root frame (yaw-only, so the hand
  // moves with the body and not with the head's turns), its offset scaled to the avatar's size:
  // IK keeps its azimuth, elevation and distance from H (docs/conventions.md#translator).
  Pose other_wrist_from_head;
  TargetId head_target = kNoTarget;  // what the person's gaze designates (held with the frame)
  // How far the person's own gaze is from their head target in their room, degrees (held with
  // the frame): near 0 while their eyes are on it (presence/gaze_settle.h).
  float person_gaze_off_deg = 180.0f;
  TargetId hand_target = kNoTarget;  // what the person's hand designates (held with the frame)
  // How far the person's own eye → fingertip ray is from their hand target in their room,
  // degrees (MPNet's IT^R, held with the frame): near 0 while they point at it
  // (presence/pointing_settle.h).
  float person_point_off_deg = 180.0f;
  nn::Progression progression{};
  float head_weight = 0.0f;
  float hand_weight = 0.0f;
};

struct TranslatorStats {
  std::uint64_t ticks = 0;
  std::uint64_t held = 0;             // ticks that reused the last valid frame
  std::uint64_t rejected_frames = 0;  // frames with a non-finite number or missing parts
  std::uint64_t unknown_targets = 0;  // target ids this room's map lacks (copied instead)
  std::uint64_t restarts = 0;  // the loop restarted because a network produced a non-finite value
};

class Translator {
 public:
  Translator(nn::Mpnet mpnet, nn::Ugnet ugnet, const TranslatorConfig& config);

  // One tick. `frame` is null when no frame arrived in time (a gap in the stream).
  AvatarFrame tick(const TrackingFrame* frame, const LocalTargets& room);

  // tick() in halves, so that many translators' networks run as one batch
  // (gesture/translator_batch.h): begin_tick() does everything before the networks and says
  // whether they must run; if so, the caller runs MPNet on mpnet_window() and hands its
  // progression to take_progression(), then UGNet on ugnet_window() with ugnet_noise() and hands
  // its prediction to end_tick(). tick_result() is then what tick() returns; tick() is exactly
  // this with the networks run one by one (run_networks()).
  bool begin_tick(const TrackingFrame* frame, const LocalTargets& room);
  nn::MpnetWindow mpnet_window() const { return loop_.mpnet_window(); }
  void take_progression(const nn::Progression& progression);
  nn::UgnetWindow ugnet_window() const { return loop_.ugnet_window(); }
  std::span<const float> ugnet_noise() const;
  void end_tick(const nn::PoseVector& prediction);
  void run_networks();
  const AvatarFrame& tick_result() const { return result_; }
  const nn::Mpnet& mpnet() const { return loop_.mpnet(); }
  const nn::Ugnet& ugnet() const { return loop_.ugnet(); }

  const TranslatorStats& stats() const { return stats_; }
  float scale() const { return loop_.scale(); }
  const TranslatorConfig& config() const { return config_; }
  // Moves the avatar's root O (yaw only) from the next tick on. The avatar's end-effectors are
  // relative to O, so the whole pose moves with it (presence/body_turn.h turns the body this
  // way); nothing in the windows changes. Allocates nothing.
  void set_avatar_root(const Pose& T_world_avatar_root) {
    config_.T_world_avatar_root = T_world_avatar_root;
  }

 private:
  bool usable(const TrackingFrame& frame) const;
  Vec3 avatar_target_position(TargetId id, const Vec3& user_position, const LocalTargets& room);
  TranslationInput input_for(const TrackingFrame& frame, const LocalTargets& room);
  std::span<const float> draw_noise();
  void finish_tick();  // the tick's result from the loop's step

  TranslatorConfig config_;
  TranslationLoop loop_;
  bool started_ = false;
  TrackingFrame last_valid_;
  Pose last_other_wrist_from_head_;  // the non-deictic hand may be lost on its own
  TranslatorStats stats_;
  std::mt19937 rng_;
  std::array<float, nn::kDiffusionNoiseSize> noise_{};
  bool needs_noise_ = false;
  // The tick under way (begin_tick() … end_tick()) and its result.
  TranslationInput input_;
  TranslationStep step_;
  AvatarFrame result_;
};

}  // namespace deixis
