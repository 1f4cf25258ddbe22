#include "capture/actor.h"

#include <algorithm>
#include <cmath>

#include "capture/completion.h"
#include "core/error.h"

namespace deixis::capture {

namespace {

float angle_between(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0f, 1.0f));
}

// Saccade duration by the main sequence: ≈ 2.2–2.7 ms per degree plus ≈ 25 ms.
double saccade_duration(float amplitude) {
  return std::min(0.025 + 0.13 * static_cast<double>(amplitude), 0.20);
}

// The mirror image of a torso-frame wrist pose in the sagittal plane: the other hand's pose.
Pose mirrored(const Pose& p) {
  const Mat3 M = Vec3(-1, 1, 1).asDiagonal();
  return Pose{M * p.rotation * M, M * p.translation};
}

Mat3 rotation_about(const Vec3& axis, float angle) {
  return Eigen::AngleAxisf(angle, axis.normalized()).toRotationMatrix();
}

// Free-form movement keeps clear of the targets: the fingertip at least 15 cm from the hand target
// and 15° off the line of sight to it, the gaze at least 25° away from the head target.
constexpr float kFreeFormClearance = 0.15f;
constexpr float kFreeFormAngle = 0.26f;
constexpr float kFreeFormGazeAngle = 0.44f;

constexpr double kPeakSpeedLimit = 2.3;  // m/s

}  // namespace

float twist_toward(const Motion& motion, const Vec3& target) {
  const Vec3 local = motion.stance().rotation.transpose() * (target - motion.stance().translation);
  const float azimuth = std::atan2(-local.x(), -local.z());  // positive to the left
  return 0.12f * std::clamp(azimuth, -1.3f, 1.3f);
}

std::optional<TorsoKey> touch_torso(const Motion& motion, const TargetObject& target) {
  TorsoKey key{0.0f, 0.0f, twist_toward(motion, target.position)};
  for (int step = 0; step <= 10; ++step) {
    key.lean = 0.04f * static_cast<float>(step);
    if (touching_pose(motion.body(), motion.deictic_hand(), motion.torso_pose(key), target)) {
      return key;
    }
  }
  return std::nullopt;
}

Actor::Actor(Motion& motion, Labelling& labels, Random& rng)
    : motion_(motion), labels_(labels), rng_(rng), hand_(motion.deictic_hand()) {}

double Actor::scaled(double seconds) const {
  return seconds / static_cast<double>(motion_.body().subject.speed);
}

double Actor::movement_duration(double distance, double width, double intercept, double slope) {
  const double fitts =
      scaled(fitts_duration(distance, width, intercept, slope)) * rng_.uniform(0.9, 1.1);
  // A minimum-jerk movement peaks at 1.875·D/T; comfortable reaches stay below ≈ 2.3 m/s.
  return std::max(fitts, 1.875 * distance / kPeakSpeedLimit);
}

Pose Actor::predicted_torso(double t) const {
  const auto s = motion_.torso.at(t);
  const Pose a = motion_.torso_pose(*s.from);
  const Pose b = motion_.torso_pose(*s.to);
  const float u = static_cast<float>(s.s);
  return Pose{Quat(a.rotation).slerp(u, Quat(b.rotation)).toRotationMatrix(),
              a.translation + u * (b.translation - a.translation)};
}

Mat3 Actor::predicted_head(double t) const {
  const Pose torso = predicted_torso(t);
  const auto s = motion_.head.at(t);
  return Quat(motion_.head_rotation(*s.from, torso))
      .slerp(static_cast<float>(s.s), Quat(motion_.head_rotation(*s.to, torso)))
      .toRotationMatrix();
}

Pose Actor::predicted_wrist(Hand hand, double t) const {
  const Pose torso = predicted_torso(t);
  const Vec3 eye = eye_position(motion_.body(), torso, predicted_head(t), motion_.dominant_eye());
  const auto s = motion_.hands[index(hand)].at(t);
  const Pose a = motion_.wrist_pose(*s.from, hand, torso, eye);
  const Pose b = motion_.wrist_pose(*s.to, hand, torso, eye);
  const float u = static_cast<float>(s.s);
  return Pose{Quat(a.rotation).slerp(u, Quat(b.rotation)).toRotationMatrix(),
              a.translation + u * (b.translation - a.translation)};
}

GazeShift Actor::shift_gaze(double t, const GazeKey& key, const Vec3& point) {
  labels_.leave_rest(t);
  const Body& body = motion_.body();
  const Style& style = body.subject.style;
  const Pose torso_end = motion_.torso_pose(motion_.torso.last());
  const Mat3 head_now = predicted_head(t);
  const Vec3 ahead = head_now * Vec3(0, 0, -1);
  Mat3 head_end = head_now;
  float amplitude = 0;
  float head_amplitude = 0;
  for (int pass = 0; pass < 2; ++pass) {  // H moves with the head: refine once
    const Vec3 g = (point - head_position(body, torso_end, head_end)).normalized();
    amplitude = angle_between(ahead, g);
    // The head takes a share of what exceeds the eye-only range, and at least enough to keep the
    // eyes within a comfortable 26° of centre when the shift ends.
    head_amplitude = style.head_share * std::max(0.0f, amplitude - style.eye_only_range);
    head_amplitude = std::clamp(head_amplitude, std::max(0.0f, amplitude - 0.45f), amplitude);
    const float fraction = amplitude > 1e-4f ? head_amplitude / amplitude : 0.0f;
    head_end = look_rotation(slerp_direction(ahead, g, fraction));
  }
  GazeShift shift{t, t};
  motion_.gaze.move(t, saccade_duration(amplitude), key);
  shift.settled = motion_.gaze.end_time();
  if (head_amplitude > 0.02f) {
    head_end = head_end * rotation_about(Vec3::UnitZ(), rng_.uniform(-0.03f, 0.03f));
    const double duration =
        scaled(0.22 + 0.28 * static_cast<double>(head_amplitude)) * rng_.uniform(0.9, 1.1);
    motion_.head.move(t + rng_.uniform(0.01, 0.05), duration, HeadKey{Quat(head_end), false});
    shift.settled = std::max(shift.settled, motion_.head.end_time());
  }
  return shift;
}

GazeShift Actor::look_at(double t, const TargetObject& target) {
  labels_.head_target.set(t, target.id);
  const GazeShift shift = shift_gaze(t, GazeKey{target.position, false}, target.position);
  labels_.begin(labels_.gaze, t, shift.onset, shift.settled);
  return shift;
}

Reach Actor::point(double t, const TargetObject& target, bool with_gaze) {
  return reach(t, target, with_gaze, false);
}

Reach Actor::touch(double t, const TargetObject& target, bool with_gaze) {
  return reach(t, target, with_gaze, true);
}

Reach Actor::reach(double t, const TargetObject& target, bool with_gaze, bool touching) {
  const Body& body = motion_.body();
  labels_.leave_rest(t);
  labels_.hand_target.set(t, target.id);

  TorsoKey torso_key{0.0f, 0.0f, twist_toward(motion_, target.position)};
  if (touching) {
    const std::optional<TorsoKey> key = touch_torso(motion_, target);
    if (!key) {
      throw Error("capture: touch target " + std::to_string(target.id) + " is out of reach");
    }
    torso_key = *key;
  }
  // Torso first (the head rides on it), then gaze, then the hand aimed from the settled head.
  motion_.torso.move(t + 0.05, scaled(0.75) * rng_.uniform(0.9, 1.1), torso_key);
  GazeShift gaze;
  if (with_gaze) {
    gaze = look_at(t, target);
  }
  const Pose torso_end = motion_.torso_pose(torso_key);
  const Mat3 head_end = motion_.head_rotation(motion_.head.last(), torso_end);
  CompletionPose cs;
  if (touching) {
    cs = *touching_pose(body, hand_, torso_end, target);
  } else {
    cs = pointing_pose(body, hand_, torso_end, head_end, target.position);
  }

  double start = t + scaled(rng_.uniform(0.05, 0.15));  // the eyes lead the hand
  const Pose from = predicted_wrist(hand_, start);
  const double distance = (cs.wrist.translation - from.translation).norm();
  const double duration = movement_duration(distance, touching ? 0.015 : 0.03, 0.15, 0.12);
  if (with_gaze) {  // the hand arrives after the gaze has settled: a short reach starts later
    start = std::max(start, gaze.settled + rng_.uniform(0.03, 0.12) - duration);
  }
  const Vec3 forward = motion_.stance().rotation * Vec3(0, 0, -1);
  const Vec3 bulge = static_cast<float>(distance) * rng_.uniform(0.5f, 1.5f) *
                     (0.06f * forward + Vec3(0, 0.03f, 0));
  motion_.hands[index(hand_)].move(
      start, duration,
      HandKey{cs.wrist, false, bulge, !touching, target.position, cs.ray_distance});
  const auto& move = motion_.hands[index(hand_)].moves().back();
  labels_.begin(labels_.deictic, t, move.start, move.end);
  return Reach{move.start, move.end};
}

Pose Actor::gesture_pose(Hand hand, float amplitude, const Vec3& avoid) {
  Pose pose;
  const Pose torso = motion_.torso_pose(motion_.torso.last());
  const Vec3 H =
      head_position(motion_.body(), torso, motion_.head_rotation(motion_.head.last(), torso));
  for (int attempt = 0; attempt < 12; ++attempt) {
    pose = random_gesture_pose(hand, amplitude);
    const Vec3 tip = fingertip(motion_.body(), hand, compose(torso, pose));
    if ((tip - avoid).norm() > kFreeFormClearance &&
        angle_between(tip - H, avoid - H) > kFreeFormAngle) {
      break;
    }
  }
  return pose;
}

Pose Actor::random_gesture_pose(Hand hand, float amplitude) {
  const Body& body = motion_.body();
  const float side = hand == Hand::kRight ? 1.0f : -1.0f;
  const float s = body.subject.height / 1.70f;
  const Vec3 mid = 0.5f * (body.shoulder_in_torso[0] + body.shoulder_in_torso[1]);
  const Vec3 centre = mid + s * Vec3(side * 0.12f, -0.24f, -0.30f);
  const Vec3 shoulder = body.shoulder_in_torso[index(hand)];
  Vec3 p = centre;
  for (int attempt = 0; attempt < 8; ++attempt) {
    const Vec3 offset = amplitude * s *
                        Vec3(side * rng_.uniform(-0.10f, 0.16f), rng_.uniform(-0.10f, 0.14f),
                             rng_.uniform(-0.10f, 0.08f));
    p = centre + offset;
    if ((p - shoulder).norm() < 0.9f * body.reach()) {
      break;
    }
    p = centre;
  }
  const Vec3 distal =
      Vec3(-side * rng_.uniform(0.1f, 0.6f), rng_.uniform(-0.25f, 0.35f), -1.0f).normalized();
  const Vec3 lateral(side, 0, 0);
  const Vec3 dorsal = rotation_about(distal, side * rng_.uniform(-1.4f, 1.2f)) *
                      (lateral - lateral.dot(distal) * distal);
  return Pose{wrist_rotation(hand, distal, dorsal), p};
}

double Actor::gesticulate(double t, double duration, bool both_hands, const Vec3& hand_target,
                          TargetId next_hand_target) {
  labels_.leave_rest(t);
  const float amplitude = motion_.body().subject.style.gesture_amplitude;
  const Hand other_hand = other(hand_);
  auto& track = motion_.hands[index(hand_)];
  const double end = t + duration;
  double time = t;
  bool first = true;
  while (time < end) {
    if (!first && track.last().torso_relative && rng_.chance(0.35)) {
      // Beats: quick small down–up flicks around the current position.
      const HandKey base = track.last();
      const int beats = rng_.integer(2, 4);
      for (int k = 0; k < beats; ++k) {
        HandKey down = base;
        down.pose.translation +=
            amplitude * Vec3(0, -rng_.uniform(0.03f, 0.07f), -rng_.uniform(0.0f, 0.02f));
        track.move(time, scaled(rng_.uniform(0.10, 0.16)), down);
        track.move(track.end_time(), scaled(rng_.uniform(0.12, 0.18)), base);
        time = track.end_time();
      }
      continue;
    }
    // A stroke to a new point of the gesture space.
    const Pose to = gesture_pose(hand_, amplitude, hand_target);
    const Pose torso = predicted_torso(time);
    const Pose from = compose(inverse(torso), predicted_wrist(hand_, time));
    const double distance = (to.translation - from.translation).norm();
    const double stroke = movement_duration(distance, 0.05, 0.15, 0.09);
    track.move(time, stroke, HandKey{to, true});
    const auto& move = track.moves().back();
    if (first) {
      if (next_hand_target != kNoTarget) {
        // A new hand target: its progression is 0 from the moment it becomes the target.
        labels_.hand_target.set(move.start, next_hand_target);
        labels_.deictic.to(move.start, 0.0, 0.0f);
        labels_.phase_keys.push_back(move.start);
      }
      labels_.end(labels_.deictic, move.start, move.end);
      first = false;
    }
    if (both_hands) {
      HandKey echo{mirrored(to), true};
      echo.pose.translation *= 0.9f;
      motion_.hands[index(other_hand)].move(move.start + rng_.uniform(0.0, 0.08), stroke, echo);
    }
    time = move.end + rng_.uniform(0.0, 0.25);
  }
  if (both_hands) {
    auto& other_track = motion_.hands[index(other_hand)];
    other_track.move(time, scaled(0.6),
                     HandKey{motion_.body().rest_wrist_in_torso[index(other_hand)], true});
  }
  return time;
}

double Actor::look_freely(double t, double duration, const Vec3& head_target) {
  const double end = t + duration;
  double time = t;
  bool first = true;
  while (time < end) {
    const Pose torso = motion_.torso_pose(motion_.torso.last());
    const Vec3 H = head_position(motion_.body(), torso, predicted_head(time));
    Vec3 direction;
    for (int attempt = 0; attempt < 12; ++attempt) {
      direction = torso.rotation * rotation_about(Vec3::UnitY(), rng_.uniform(-0.6f, 0.6f)) *
                  rotation_about(Vec3::UnitX(), rng_.uniform(-0.35f, 0.15f)) * Vec3(0, 0, -1);
      if (angle_between(direction, head_target - H) > kFreeFormGazeAngle) {
        break;
      }
    }
    const Vec3 point = H + rng_.uniform(1.5f, 4.0f) * direction;
    const GazeShift shift = shift_gaze(time, GazeKey{point, false}, point);
    if (first) {
      labels_.end(labels_.gaze, shift.onset, shift.settled);
      first = false;
    }
    time = shift.settled + rng_.uniform(0.3, 1.0);
  }
  return time;
}

double Actor::nod(double t, double duration) {
  const Mat3 base = predicted_head(t);
  double time = t;
  while (time < t + duration) {
    const Mat3 R = base * rotation_about(Vec3::UnitY(), rng_.uniform(-0.06f, 0.06f)) *
                   rotation_about(Vec3::UnitX(), rng_.uniform(-0.08f, 0.06f));
    motion_.head.move(time, scaled(rng_.uniform(0.3, 0.6)), HeadKey{Quat(R), false});
    time = motion_.head.end_time() + rng_.uniform(0.1, 0.5);
  }
  return time;
}

double Actor::rest(double t) {
  const Body& body = motion_.body();
  double upright = t;
  // Hands back to their hanging pose.
  for (const Hand h : {hand_, other(hand_)}) {
    auto& track = motion_.hands[index(h)];
    const Pose& rest_pose = body.rest_wrist_in_torso[index(h)];
    const bool at_rest = track.last().torso_relative &&
                         track.last().pose.translation.isApprox(rest_pose.translation);
    if (at_rest) {
      continue;
    }
    const double start = t + rng_.uniform(0.0, 0.1);
    const Pose from = predicted_wrist(h, start);
    const Pose to = compose(motion_.torso_pose(TorsoKey{}), rest_pose);
    const double distance = (to.translation - from.translation).norm();
    const double duration = movement_duration(distance, 0.08, 0.25, 0.11);
    const Vec3 bulge = static_cast<float>(distance) * rng_.uniform(0.2f, 0.6f) *
                       (motion_.stance().rotation * Vec3(0, 0, -0.06f));
    track.move(start, duration, HandKey{rest_pose, true, bulge});
    const auto& move = track.moves().back();
    if (h == hand_) {
      labels_.end(labels_.deictic, move.start, move.end);
    }
    upright = std::max(upright, move.end);
  }
  // Torso upright, head level and facing ahead, eyes centred.
  motion_.torso.move(t, scaled(0.6), TorsoKey{});
  upright = std::max(upright, motion_.torso.end_time());
  const double start = t + rng_.uniform(0.0, 0.12);
  const Mat3 head_now = predicted_head(start);
  const Pose torso_end = motion_.torso_pose(TorsoKey{});
  const float amplitude =
      angle_between(head_now * Vec3(0, 0, -1), torso_end.rotation * Vec3(0, 0, -1));
  motion_.gaze.move(start, saccade_duration(amplitude), GazeKey{Vec3(0, 0, -1), true});
  const HeadKey level{Quat(rotation_about(Vec3::UnitX(), rng_.uniform(-0.03f, 0.03f))), true};
  motion_.head.move(start + rng_.uniform(0.01, 0.05),
                    scaled(0.22 + 0.28 * static_cast<double>(amplitude)) * rng_.uniform(0.9, 1.1),
                    level);
  const auto& head_move = motion_.head.moves().back();
  labels_.end(labels_.gaze, motion_.gaze.moves().back().start, head_move.end);
  upright = std::max({upright, head_move.end, motion_.gaze.end_time()});
  labels_.back_at_rest(upright);
  return upright + kIdleDelay;
}

}  // namespace deixis::capture
