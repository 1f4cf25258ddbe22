#include "capture/recorder.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "gesture/features.h"

namespace deixis::capture {

namespace {

const TargetObject& find(std::span<const TargetObject> targets, TargetId id) {
  for (const TargetObject& t : targets) {
    if (t.id == id) {
      return t;
    }
  }
  throw Error("capture: script refers to unknown target " + std::to_string(id));
}

// When the deictic wrist, moving out of the upright posture from `onset`, is first 0.25 m
// (kNearRestDistance) from its rest position; at most 1 s.
double out_of_posture(const Motion& motion, double onset, const BodyCalibration& calibration) {
  const Hand hand = motion.deictic_hand();
  const Vec3 rest =
      transform_point(calibration.T_world_root, calibration.rest_wrist_in_root[index(hand)]);
  constexpr double kStep = 1.0 / 240.0;
  for (double t = onset; t < onset + 1.0; t += kStep) {
    const Vec3 wrist = motion.posture_at(t).T_world_wrist[index(hand)].translation;
    if ((wrist - rest).norm() >= kNearRestDistance) {
      return t;
    }
  }
  return onset + 1.0;
}

}  // namespace

BodyCalibration calibrate(const Motion& motion) {
  const Body& body = motion.body();
  BodyCalibration c;
  c.height = body.subject.height;
  c.arm_length = body.subject.arm_length;
  c.deictic_hand = body.subject.handedness;
  const Pose upright = motion.torso_pose(TorsoKey{});
  c.T_world_root = Pose{motion.stance().rotation, head_position(body, upright, upright.rotation)};
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const Vec3 wrist = transform_point(upright, body.rest_wrist_in_torso[index(h)].translation);
    c.rest_wrist_in_root[index(h)] = transform_point(inverse(c.T_world_root), wrist);
  }
  return c;
}

Ramp idle_course(Labelling& labels, const Motion& motion, const BodyCalibration& calibration) {
  return labels.idle_course(
      [&](double onset) { return out_of_posture(motion, onset, calibration); });
}

void record(const Motion& motion, const Labelling& labels, const Ramp& idle,
            std::span<const TargetObject> targets, double end, Sequence& s) {
  const auto n = static_cast<std::size_t>(std::floor(end * kFrameRate)) + 1;
  s.frames.reserve(n);
  s.labels.reserve(n);
  s.joints.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / kFrameRate;
    const Posture posture = motion.posture_at(t);
    const Joints joints = solve_joints(motion.body(), posture);
    TrackingFrame f = track(posture, joints);
    f.time = t;
    f.head_target = labels.head_target.at(t);
    f.hand_target = labels.hand_target.at(t);
    f.head_target_position = find(targets, f.head_target).position;
    f.hand_target_position = find(targets, f.hand_target).position;
    s.frames.push_back(f);
    s.joints.push_back(joints);
    s.labels.push_back({labels.gaze.value_at(t), labels.deictic.value_at(t), idle.value_at(t)});
  }
  s.phase_keys.assign(n, 0);
  for (const double k : labels.phase_keys) {
    const auto i = static_cast<long>(std::lround(k * kFrameRate));
    if (i >= 0 && static_cast<std::size_t>(i) < n) {
      s.phase_keys[static_cast<std::size_t>(i)] = 1;
    }
  }
}

}  // namespace deixis::capture
