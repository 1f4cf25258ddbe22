#include "capture/script.h"

#include <numbers>

#include "capture/actor.h"
#include "capture/recorder.h"
#include "capture/targets.h"

namespace deixis::capture {

namespace {

// One performance: the body, its motion, the labels and the targets being written.
class Performance {
 public:
  Performance(const Subject& subject, Category category, std::uint64_t seed,
              const TargetRules& rules)
      : body_(make_body(subject)),
        rng_(seed),
        motion_rng_(rng_.fork(1)),
        motion_(body_, random_stance(rng_), motion_rng_),
        actor_(motion_, labels_, rng_),
        sampler_(motion_, rng_, rules),
        category_(category) {}

  Sequence run(const Subject& subject, std::uint64_t seed) {
    const double end = script();
    Sequence s;
    s.subject = subject.name;
    s.category = category_;
    s.seed = seed;
    s.dominant_eye = subject.dominant_eye;
    s.calibration = calibrate(motion_);
    s.targets = targets_;
    const Ramp idle = idle_course(labels_, motion_, s.calibration);
    record(motion_, labels_, idle, targets_, end, s);
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

Sequence perform(const Subject& subject, Category category, std::uint64_t seed,
                 const TargetRules& rules) {
  Performance performance(subject, category, seed, rules);
  return performance.run(subject, seed);
}

}  // namespace deixis::capture
