#include "capture/script.h"

#include <cmath>
#include <numbers>

#include "capture/actor.h"
#include "capture/targets.h"
#include "gesture/error.h"
#include "gesture/features.h"

namespace deixis::capture {

namespace {

// One performance: the body, its motion, the labels and the targets being written.
class Performance {
 public:
  Performance(const Subject& subject, Category category, std::uint64_t seed)
      : body_(make_body(subject)),
        rng_(seed),
        motion_rng_(rng_.fork(1)),
        motion_(body_, random_stance(rng_), motion_rng_),
        actor_(motion_, labels_, rng_),
        sampler_(motion_, rng_),
        category_(category) {}

  Sequence run(const Subject& subject, std::uint64_t seed) {
    const double end = script();
    Sequence s;
    s.subject = subject.name;
    s.category = category_;
    s.seed = seed;
    s.dominant_eye = subject.dominant_eye;
    s.calibration = calibration();
    s.targets = targets_;
    const Ramp idle =
        labels_.idle_course([&](double onset) { return out_of_posture(onset, s.calibration); });
    record(end, idle, s);
    return s;
  }

 private:
  static Pose random_stance(Random& rng) {
    // Anywhere in a room, facing anywhere: features must not depend on where the person stands.
    const float yaw = rng.uniform(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
    return Pose{yaw_rotation(yaw), Vec3(rng.uniform(-2.0f, 2.0f), 0, rng.uniform(-2.0f, 2.0f))};
  }

  bool touching() const { return is_touching(category_); }

  TargetObject object() {
    const auto id = static_cast<TargetId>(targets_.size() + 1);
    TargetObject t = touching() ? sampler_.touching(id, targets_) : sampler_.pointing(id, targets_);
    targets_.push_back(t);
    return t;
  }
  TargetObject glance_target() {  // the second target of a gaze shift: anything in view
    const auto id = static_cast<TargetId>(targets_.size() + 1);
    TargetObject t = touching() && rng_.chance(0.5) ? sampler_.touching(id, targets_)
                                                    : sampler_.pointing(id, targets_);
    targets_.push_back(t);
    return t;
  }
  TargetObject partner() {
    TargetObject t = sampler_.partner(targets_);
    targets_.push_back(t);
    return t;
  }

  Reach deictic(double t, const TargetObject& target, bool with_gaze) {
    return touching() ? actor_.touch(t, target, true) : actor_.point(t, target, with_gaze);
  }

  void initial_targets(const TargetObject& head, const TargetObject& hand) {
    labels_.head_target.set(0.0, head.id);
    labels_.hand_target.set(0.0, hand.id);
  }

  double hold() { return rng_.uniform(0.8, 1.8); }

  // The script of each category; returns the end time.
  double script() {
    double t = rng_.uniform(0.6, 1.4);  // standing upright first
    switch (category_) {
      case Category::kPointingSingle:
      case Category::kTouchingSingle: {
        const TargetObject target = object();
        initial_targets(target, target);
        t = deictic(t, target, true).complete + hold();
        break;
      }
      case Category::kPointingTwoTargets:
      case Category::kTouchingTwoTargets: {
        const TargetObject a = object();
        const TargetObject b = object();
        initial_targets(a, a);
        t = deictic(t, a, true).complete + rng_.uniform(0.7, 1.5);
        t = deictic(t, b, true).complete + rng_.uniform(0.7, 1.5);
        break;
      }
      case Category::kPointingGazeShift:
      case Category::kTouchingGazeShift: {
        const TargetObject first = object();
        const TargetObject second = glance_target();
        initial_targets(first, first);
        t = deictic(t, first, true).complete + rng_.uniform(0.5, 1.0);
        t = actor_.look_at(t, second).settled + rng_.uniform(0.5, 1.2);
        t = actor_.look_at(t, first).settled + rng_.uniform(0.5, 1.0);
        break;
      }
      case Category::kPointingExplanation:
      case Category::kTouchingExplanation:
        t = explanation(t);
        break;
      case Category::kPointingTransition:
      case Category::kTouchingTransition:
        t = transition(t);
        break;
    }
    return actor_.rest(t) + rng_.uniform(0.4, 1.0);
  }

  // Explaining to a person (the partner, target 0) with free-form gestures, pointing at or
  // touching an object, and explaining again.
  double explanation(double t) {
    const TargetObject listener = partner();
    const TargetObject target = object();
    initial_targets(listener, listener);
    t = explain(t, listener, rng_.uniform(1.5, 3.0));
    const bool with_gaze = touching() || rng_.chance(0.7);
    t = deictic(t, target, with_gaze).complete + rng_.uniform(0.6, 1.5);
    // Back to explaining: the hand leaves the object and gestures toward the listener again, who
    // becomes the hand target as it leaves.
    return explain(t, listener, rng_.uniform(1.2, 2.5), target.position);
  }

  double explain(double t, const TargetObject& listener, double duration) {
    return explain(t, listener, duration, listener.position);
  }
  double explain(double t, const TargetObject& listener, double duration, const Vec3& leaving) {
    double gaze_settled = t;
    if (labels_.head_target.last() != listener.id || labels_.gaze.last() < 1.0f) {
      gaze_settled = actor_.look_at(t, listener).settled;
    }
    const TargetId next = labels_.hand_target.last() != listener.id ? listener.id : kNoTarget;
    const double hands_end =
        actor_.gesticulate(t + rng_.uniform(0.0, 0.2), duration, rng_.chance(0.4), leaving, next);
    const double nods_end = actor_.nod(gaze_settled + 0.1, hands_end - gaze_settled - 0.1);
    return std::max(hands_end, nods_end) + rng_.uniform(0.0, 0.2);
  }

  // Alternating a deictic gesture at one target with free-form gestures.
  double transition(double t) {
    const TargetObject target = object();
    initial_targets(target, target);
    const int episodes = rng_.integer(2, 3);
    for (int e = 0; e < episodes; ++e) {
      t = deictic(t, target, true).complete + rng_.uniform(0.6, 1.5);
      if (e + 1 < episodes) {
        const double duration = rng_.uniform(1.5, 3.0);
        const double head_end = actor_.look_freely(t, duration, target.position);
        const double hands_end = actor_.gesticulate(t + rng_.uniform(0.0, 0.15), duration,
                                                    rng_.chance(0.3), target.position);
        t = std::max(head_end, hands_end) + rng_.uniform(0.0, 0.2);
      }
    }
    return t;
  }

  BodyCalibration calibration() const {
    BodyCalibration c;
    c.height = body_.subject.height;
    c.arm_length = body_.subject.arm_length;
    c.deictic_hand = body_.subject.handedness;
    // Root O: H in the upright posture (no sway), yaw-only (paper §IV.A).
    const Pose upright = motion_.torso_pose(TorsoKey{});
    c.T_world_root =
        Pose{motion_.stance().rotation, head_position(body_, upright, upright.rotation)};
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      const Vec3 wrist = transform_point(upright, body_.rest_wrist_in_torso[index(h)].translation);
      c.rest_wrist_in_root[index(h)] = transform_point(inverse(c.T_world_root), wrist);
    }
    return c;
  }

  const TargetObject& find(TargetId id) const {
    for (const TargetObject& t : targets_) {
      if (t.id == id) {
        return t;
      }
    }
    throw Error("capture: script refers to unknown target " + std::to_string(id));
  }

  // When the deictic wrist, moving out of the upright posture from `onset`, is first 0.25 m
  // (kNearRestDistance) from its rest position; at most 1 s.
  double out_of_posture(double onset, const BodyCalibration& calibration) const {
    const Hand hand = body_.subject.handedness;
    const Vec3 rest =
        transform_point(calibration.T_world_root, calibration.rest_wrist_in_root[index(hand)]);
    constexpr double kStep = 1.0 / 240.0;
    for (double t = onset; t < onset + 1.0; t += kStep) {
      const Vec3 wrist = motion_.posture_at(t).T_world_wrist[index(hand)].translation;
      if ((wrist - rest).norm() >= kNearRestDistance) {
        return t;
      }
    }
    return onset + 1.0;
  }

  void record(double end, const Ramp& idle, Sequence& s) const {
    const auto n = static_cast<std::size_t>(std::floor(end * kFrameRate)) + 1;
    s.frames.reserve(n);
    s.labels.reserve(n);
    s.joints.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / kFrameRate;
      const Posture posture = motion_.posture_at(t);
      const Joints joints = solve_joints(body_, posture);
      TrackingFrame f = track(posture, joints);
      f.time = t;
      f.head_target = labels_.head_target.at(t);
      f.hand_target = labels_.hand_target.at(t);
      f.head_target_position = find(f.head_target).position;
      f.hand_target_position = find(f.hand_target).position;
      s.frames.push_back(f);
      s.joints.push_back(joints);
      s.labels.push_back({labels_.gaze.value_at(t), labels_.deictic.value_at(t), idle.value_at(t)});
    }
    s.phase_keys.assign(n, 0);
    for (const double k : labels_.phase_keys) {
      const auto i = static_cast<long>(std::lround(k * kFrameRate));
      if (i >= 0 && static_cast<std::size_t>(i) < n) {
        s.phase_keys[static_cast<std::size_t>(i)] = 1;
      }
    }
  }

  const Body body_;
  Random rng_;
  Random motion_rng_;
  Motion motion_;
  Labelling labels_;
  Actor actor_;
  TargetSampler sampler_;
  Category category_;
  std::vector<TargetObject> targets_;
};

}  // namespace

Sequence perform(const Subject& subject, Category category, std::uint64_t seed) {
  Performance performance(subject, category, seed);
  return performance.run(subject, seed);
}

}  // namespace deixis::capture
