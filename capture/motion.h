#pragma once
// The motion of one person over time: a track per channel (torso, head, gaze, each wrist) of
// minimum-jerk moves (timeline.h), resolved into a posture at any instant, plus standing sway and
// small head drift. The behaviours that fill the tracks are in actor.h.
//
// Channels are resolved in dependency order: torso (with sway) → head (with drift) → H → gaze
// (eyes clamped to their range of motion) → wrists (a pointing hand keeps its fingertip on the
// dominant eye's ray to the target).

#include <array>

#include "capture/body.h"
#include "capture/posture.h"
#include "capture/random.h"
#include "capture/timeline.h"

namespace deixis::capture {

// Torso angles about the hip pivot (rad): forward lean, sideways bend, twist about the spine.
struct TorsoKey {
  float lean = 0;
  float side = 0;
  float twist = 0;
};

// Head orientation, in the world (fixed while gaze holds a target) or relative to the torso.
struct HeadKey {
  Quat rotation = Quat::Identity();
  bool torso_relative = true;
};

// Where the eyes look: a fixation point in the world, or a direction in the head frame.
struct GazeKey {
  Vec3 value = Vec3(0, 0, -1);
  bool head_relative = true;
};

// Where a wrist is: a pose in the torso frame or the world. `bulge` bends the path of the move
// into this key sideways (world offset at mid-path; paths of real reaches curve slightly).
// Pointing keys servo: the wrist translates so the fingertip stays `servo_distance` along the
// dominant eye's ray to `servo_target` (people hold the eye–finger alignment while pointing).
struct HandKey {
  Pose pose;
  bool torso_relative = true;
  Vec3 bulge = Vec3::Zero();
  bool servo = false;
  Vec3 servo_target = Vec3::Zero();
  float servo_distance = 0;
};

// The eyes' range of motion in the head (rad, about 40°; Guitton & Volle 1987).
inline constexpr float kEyeRange = 0.70f;

class Motion {
 public:
  Motion(const Body& body, const Pose& T_world_stance, Random& rng);

  const Body& body() const { return *body_; }
  const Pose& stance() const { return T_world_stance_; }
  Hand deictic_hand() const { return body_->subject.handedness; }
  Eye dominant_eye() const { return body_->subject.dominant_eye; }

  Track<TorsoKey> torso;
  Track<HeadKey> head;
  Track<GazeKey> gaze;
  std::array<Track<HandKey>, 2> hands;  // by Hand

  // Resolution of single keys (no sway or drift): what the planner predicts.
  Pose torso_pose(const TorsoKey& key) const;
  Mat3 head_rotation(const HeadKey& key, const Pose& T_world_torso) const;
  Pose wrist_pose(const HandKey& key, Hand hand, const Pose& T_world_torso,
                  const Vec3& dominant_eye) const;

  // Everything at time t.
  Posture posture_at(double t) const;

 private:
  Vec3 sway(double t) const;
  Mat3 drift(double t) const;

  const Body* body_;
  Pose T_world_stance_;
  // Sums of sinusoids (amplitude, angular frequency, phase) for sway (x, y, z) and drift (yaw,
  // pitch).
  struct Wave {
    float amplitude;
    float omega;
    float phase;
  };
  std::array<std::array<Wave, 3>, 3> sway_{};
  std::array<std::array<Wave, 2>, 2> drift_{};
};

// Direction interpolation on the sphere (minimum-jerk progress s).
Vec3 slerp_direction(const Vec3& a, const Vec3& b, float s);
// A head rotation looking along `forward` with the head's up as close to world up as allowed.
Mat3 look_rotation(const Vec3& forward, const Vec3& up = Vec3::UnitY());

}  // namespace deixis::capture
