#pragma once
// The simulator's virtual user (docs/sim.md): a synthetic-capture person (capture/) standing in
// the local room, driven live instead of by a script. Each command plans the capture's own
// motion at the current time (minimum-jerk reaches with Fitts-like durations, eyes leading the
// head, the torso twisting or leaning as a touch needs), queued behind any movement still in
// progress, and sample() reports what a headset would track at any instant.
//
// Commands append to the motion's tracks (they allocate, at the user's pace); sample() allocates
// nothing, so the 30 Hz tick stays allocation-free.

#include <cstdint>
#include <string>
#include <vector>

#include "capture/actor.h"
#include "capture/labelling.h"
#include "capture/motion.h"
#include "capture/subject.h"

namespace deixis::sim {

struct SimUserScene {
  Pose T_world_floor;                 // where the user stands: floor point, yaw only
  std::vector<TargetObject> objects;  // the local room's objects (ids ≥ 1)
  Vec3 partner_head = Vec3::Zero();   // target 0: the remote person's avatar's eyes
};

// Where the user looks, relative to their stance: yaw turns left (+) about +Y, pitch up (+).
struct LookAngles {
  float yaw = 0.0f;    // rad
  float pitch = 0.0f;  // rad
};

class SimUser {
 public:
  SimUser(const capture::Subject& subject, const SimUserScene& scene, std::uint64_t seed);
  SimUser(const SimUser&) = delete;
  SimUser& operator=(const SimUser&) = delete;

  // Free look: eyes then head turn toward `look` (a saccade-sized step at a time; the latest
  // wish is followed once the movement in progress ends, see update()). The head target stays
  // what it was, as when a person glances away from it.
  void look(LookAngles look);
  // Plans what look() asked for when the eyes and head are free; call once per tick.
  void update(double t);
  // Looks at the other person (target 0).
  void look_at_partner(double t);
  // Points at / touches object `id` (looking at it too). An empty string when planned, else why
  // not ("no object 9", "Cup is out of reach").
  std::string point(double t, TargetId id);
  std::string touch(double t, TargetId id);
  // Free-form gestures toward the other person for `seconds`.
  void explain(double t, double seconds);
  // Back to the upright, idle posture.
  void rest(double t);

  // What a tracker reports at `t`, with the head and hand targets of that moment.
  TrackingFrame sample(double t) const;

  // The deictic progression the capture labels at `t` (for drawing the user's pointing ray).
  float deictic(double t) const { return labels_.deictic.value_at(t); }
  const BodyCalibration& calibration() const { return calibration_; }
  LookAngles look_angles() const { return wanted_; }
  // The look angles of a world point seen from the user's eyes in the upright posture.
  LookAngles angles_toward(const Vec3& p_world) const;

 private:
  const TargetObject* find(TargetId id) const;
  Vec3 look_direction(LookAngles look) const;

  capture::Body body_;
  capture::Random rng_;
  capture::Random motion_rng_;
  capture::Motion motion_;
  capture::Labelling labels_;
  capture::Actor actor_;
  std::vector<TargetObject> targets_;  // the room's objects and the partner (id 0)
  BodyCalibration calibration_;
  LookAngles wanted_;
  LookAngles planned_;
};

}  // namespace deixis::sim
