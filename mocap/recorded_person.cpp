#include "mocap/recorded_person.h"

namespace deixis::mocap {

namespace {

constexpr float kEyeHeightRatio = 0.936f;  // eye height / stature (gesture/upright_calibration)
constexpr float kReferenceHeight = 1.70f;  // BodyCalibration's default rest wrists' stature

}  // namespace

Pose recording_placement(SkeletonTracking& tracking, const Pose& T_world_floor) {
  return compose(T_world_floor, inverse(tracking.ground(0)));
}

void place(const Pose& T_world_recording, TrackingFrame& frame) {
  frame.T_world_head = compose(T_world_recording, frame.T_world_head);
  frame.gaze = transform_direction(T_world_recording, frame.gaze);
  for (std::size_t h = 0; h < 2; ++h) {
    frame.T_world_wrist[h] = compose(T_world_recording, frame.T_world_wrist[h]);
    frame.index_tip[h] = transform_point(T_world_recording, frame.index_tip[h]);
  }
}

BodyCalibration stated_calibration(const StatedBody& body, Hand deictic_hand,
                                   const Pose& T_world_floor) {
  BodyCalibration c;
  c.height = body.height;
  c.arm_length = body.arm_length;
  c.deictic_hand = deictic_hand;
  c.T_world_root =
      compose(T_world_floor, Pose{Mat3::Identity(), Vec3(0, kEyeHeightRatio * c.height, 0)});
  const BodyCalibration defaults;
  for (std::size_t h = 0; h < 2; ++h) {
    c.rest_wrist_in_root[h] = defaults.rest_wrist_in_root[h] * (c.height / kReferenceHeight);
  }
  return c;
}

RecordedPerson perform_recording(const Bvh& bvh, const RecordingPlay& play,
                                 const Pose& T_world_floor, double seconds, double rate) {
  BvhPlayer player(bvh, play.metres_per_unit, play.playback);
  const Pose T_world_recording = recording_placement(player.tracking(), T_world_floor);
  RecordedPerson person;
  if (play.body) {
    person.body = stated_calibration(*play.body, play.deictic_hand, T_world_floor);
  } else {
    person.body = player.tracking().calibrate(play.deictic_hand);
    person.body.T_world_root = compose(T_world_recording, person.body.T_world_root);
  }
  const double span = seconds > 0.0 ? seconds : player.duration();
  const auto count = sample_count(span, rate);
  person.frames.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / rate;
    player.at(t, person.frames[i]);
    place(T_world_recording, person.frames[i]);
  }
  return person;
}

}  // namespace deixis::mocap
