#pragma once
// Where the remote person's pointing and touching end, seen from this site, and how far the
// avatar's gesture is from this room's copy of the target there, next to the copy-paste
// baseline (presence/pose_copy.h).
//
// The receiving site has only what arrives over the network (no labels, no script), so it finds
// completion states as an observer would: while the person's hand target is an object, the
// fingertip moves (faster than 0.3 m/s, on the sender's clock), settles (slower than 0.08 m/s) away
// from the upright posture (the wrist 0.25 m or more from its rest position) and holds; the last
// frame of the hold (before the hand moves off or the target changes) is the completion state, as
// in tests/presence/end_to_end_test.cpp. A hold with the fingertip within 5 cm of the object's
// surface in the person's own room is a touch, any other a point. Errors, in the avatar's root
// frame (paper §V.A): pointing, the horizontal and vertical angles between the eye-midpoint →
// fingertip ray and the ray to the object's centre; touching, the fingertip's distance from the
// object's surface.
//
// observe() runs once per played frame and allocates nothing: samples go into storage reserved
// at construction (the rest are counted and dropped).

#include <cstdint>
#include <span>
#include <vector>

#include "core/target_map.h"
#include "presence/pose_copy.h"
#include "presence/remote_avatar.h"

namespace deixis::eval {

struct DeicticError {
  double horizontal_deg = 0.0;  // pointing
  double vertical_deg = 0.0;
  double touch_cm = 0.0;  // touching
};

// Not measured (NaN in every field): e.g. the networks' chain where a caller gave none.
DeicticError unmeasured();

struct DeicticSample {
  double time = 0.0;           // s, this site's clock since streaming began
  std::uint32_t sequence = 0;  // the frame's sequence number
  TargetId target = kNoTarget;
  bool touching = false;
  DeicticError avatar;  // the translated avatar after IK
  DeicticError copy;    // the pose copied unchanged
  // Where an avatar's error comes from (docs/live-rooms.md, "Where the error comes from"): the
  // networks' own end-effectors before IK (H and the fingertip the translator gave IK), measured
  // the same way; how far pointing settling, touch contact and IK together moved the fingertip
  // off them (cm; the field keeps IK's name); the person's own gesture in their room against
  // their copy of the target (their root frame); and how long the hold had lasted at its last
  // frame (s, this site's clock).
  DeicticError network;
  double ik_fingertip_cm = 0.0;
  DeicticError person;
  double hold_s = 0.0;
};

// What the avatar shows this frame: its eye midpoint H and deictic fingertip (world, after IK),
// and its root O this frame, in which its pointing errors are measured: turned with its body
// when it turns toward a target (presence/body_turn.h), as the paper measures in the avatar's
// root. Measured from the spot's unturned facing instead, the vertical error of a target far to
// the side is ill-conditioned (docs/decisions.md §81).
struct AvatarChain {
  Vec3 eye_midpoint = Vec3::Zero();
  Vec3 fingertip = Vec3::Zero();
  Pose T_world_root;
  // The networks' end-effectors this tick, before IK (the translator's H and fingertip,
  // presence::RemoteAvatar::frame()); without them the sample's `network` is unmeasured.
  bool has_network = false;
  Vec3 network_head = Vec3::Zero();
  Vec3 network_fingertip = Vec3::Zero();
};

// A translated avatar's chain this tick: after IK, and the networks' before it.
AvatarChain chain_of(const presence::RemoteAvatar& avatar);

class DeicticObserver {
 public:
  explicit DeicticObserver(std::size_t capacity);

  // One played frame of the remote person (their room), the avatar's chain after this tick, the
  // copy of the person onto the avatar's spot (measured in its own root), this room, and the
  // person's room (null until its map arrives).
  void observe(const TrackingFrame& frame, std::uint32_t sequence, double time,
               const AvatarChain& avatar, const presence::PoseCopy& copy, const TargetMap& room,
               const TargetMap* remote_room);
  // The stream stopped or ended: a hold in progress ends here.
  void interrupt();

  std::span<const DeicticSample> samples() const { return samples_; }
  std::uint64_t dropped() const { return dropped_; }

 private:
  enum class Phase : std::uint8_t { kWaiting, kMoving, kHolding };
  void end_hold();
  void commit();
  DeicticSample measure(const TrackingFrame& frame, std::uint32_t sequence, double time,
                        const AvatarChain& avatar, const presence::PoseCopy& copy,
                        const TargetObject& object, bool touching) const;

  std::vector<DeicticSample> samples_;
  std::uint64_t dropped_ = 0;
  Phase phase_ = Phase::kWaiting;
  TargetId target_ = kNoTarget;
  bool has_previous_ = false;
  Vec3 previous_tip_ = Vec3::Zero();
  double previous_sender_time_ = 0.0;  // s, the previous frame's TrackingFrame::time
  DeicticSample candidate_;
  double hold_start_ = 0.0;  // s, when the current hold began
};

}  // namespace deixis::eval
