#include "capture/virtual_user.h"

#include <algorithm>
#include <string>

#include "capture/actor.h"
#include "capture/recorder.h"
#include "core/error.h"

namespace deixis::capture {

namespace {

constexpr double kLeadIn = 0.5;       // s upright before the first step (a tracker's first frames)
constexpr double kTail = 0.5;         // s recorded after the last step
constexpr double kMinCycle = 0.5;     // s a repetition takes at least, so a script of instant
                                      // steps cannot repeat forever
constexpr float kPartnerSize = 0.2f;  // m: the partner's head as a target object

// One person performing a script in one room.
class ScriptedPerson {
 public:
  ScriptedPerson(const Subject& subject, const VirtualUserScene& scene, std::uint64_t seed)
      : body_(make_body(subject)),
        rng_(seed),
        motion_rng_(rng_.fork(1)),
        motion_(body_, scene.T_world_floor, motion_rng_),
        actor_(motion_, labels_, rng_) {
    targets_.assign(scene.objects.begin(), scene.objects.end());
    targets_.push_back({kPartnerTarget, "partner", TargetKind::kSphere, scene.partner_head,
                        Vec3::Constant(kPartnerSize)});
    // People are looked and pointed at as objects are: a head-sized sphere where their eyes are.
    for (const ScenePerson& person : scene.people) {
      targets_.push_back({person.target, person.site, TargetKind::kSphere, person.head,
                          Vec3::Constant(kPartnerSize)});
    }
    // Standing upright facing the other person: they are what the person attends to until the
    // script says otherwise (the translator needs a head and a hand target in every frame).
    labels_.head_target.set(0.0, kPartnerTarget);
    labels_.hand_target.set(0.0, kPartnerTarget);
  }

  ScriptPerformance run(std::span<const ScriptStep> script, double min_seconds) {
    ScriptPerformance out;
    double t = kLeadIn;
    for (int cycle = 0; cycle == 0 || t < min_seconds; ++cycle) {
      const double cycle_start = t;
      for (std::size_t i = 0; i < script.size(); ++i) {
        StepTiming timing{i, cycle, script[i].action, script[i].target, t, t, t};
        perform_step(script, i, timing);
        out.steps.push_back(timing);
        t = timing.end;
      }
      t = std::max(t, cycle_start + kMinCycle);
    }
    Sequence& s = out.sequence;
    s.subject = body_.subject.name;
    s.category = Category::kPointingExplanation;  // the closest of the paper's categories
    s.dominant_eye = body_.subject.dominant_eye;
    s.calibration = calibrate(motion_);
    s.targets = targets_;
    const Ramp idle = idle_course(labels_, motion_, s.calibration);
    record(motion_, labels_, idle, targets_, t + kTail, s);
    return out;
  }

 private:
  // Performs script[i] from timing.start; fills its completion and end. Errors name the step.
  void perform_step(std::span<const ScriptStep> script, std::size_t i, StepTiming& timing) {
    const ScriptStep& step = script[i];
    try {
      timing.complete = perform(step, timing.start);
    } catch (const Error& e) {
      throw Error("virtual user: script[" + std::to_string(i) + "] (" +
                  std::string(action_name(step.action)) + "): " + e.what());
    }
    // Explaining lasts its seconds; every other step holds its state for them after arriving.
    timing.end = step.action == ScriptStep::Action::kExplain
                     ? timing.complete
                     : timing.complete + static_cast<double>(step.seconds);
  }

  double perform(const ScriptStep& step, double t) {
    switch (step.action) {
      case ScriptStep::Action::kLookAt:
        return actor_.look_at(t, target(step.target)).settled;
      case ScriptStep::Action::kPoint:
        return actor_.point(t, target(step.target), true).complete;
      case ScriptStep::Action::kTouch:
        return actor_.touch(t, target(step.target), true).complete;
      case ScriptStep::Action::kExplain:
        return explain(t, static_cast<double>(step.seconds));
      case ScriptStep::Action::kRest:
        return actor_.rest(t);
    }
    return t;
  }

  // Free-form gestures to the other person while looking at them (as script.cpp's explanation
  // categories do): the hand leaves whatever it designated, and the partner becomes the hand
  // target as it does.
  double explain(double t, double duration) {
    const TargetObject& listener = target(kPartnerTarget);
    double gaze_settled = t;
    if (labels_.head_target.last() != kPartnerTarget || labels_.gaze.last() < 1.0f) {
      gaze_settled = actor_.look_at(t, listener).settled;
    }
    const TargetId current = labels_.hand_target.last();
    const TargetId next = current != kPartnerTarget ? kPartnerTarget : kNoTarget;
    const Vec3 leaving = target(current).position;
    const double hands_end =
        actor_.gesticulate(t + rng_.uniform(0.0, 0.2), duration, rng_.chance(0.4), leaving, next);
    const double nods_end = actor_.nod(gaze_settled + 0.1, hands_end - gaze_settled - 0.1);
    return std::max(hands_end, nods_end);
  }

  const TargetObject& target(TargetId id) const {
    for (const TargetObject& t : targets_) {
      if (t.id == id) {
        return t;
      }
    }
    if (is_script_person_target(id)) {
      throw Error("no person #" + std::to_string(script_person_index(id)) + " in the room");
    }
    throw Error("no object with id " + std::to_string(id) + " in the room");
  }

  const Body body_;
  Random rng_;
  Random motion_rng_;
  Motion motion_;
  Labelling labels_;
  Actor actor_;
  std::vector<TargetObject> targets_;
};

}  // namespace

ScriptPerformance perform_script(const Subject& subject, std::span<const ScriptStep> script,
                                 const VirtualUserScene& scene, std::uint64_t seed,
                                 double min_seconds) {
  if (script.empty()) {
    throw Error("virtual user: the script has no steps");
  }
  ScriptedPerson person(subject, scene, seed);
  return person.run(script, min_seconds);
}

ScriptPerformance unscripted_performance(const BodyCalibration& body,
                                         std::vector<TrackingFrame> frames) {
  ScriptPerformance performance;
  performance.sequence.calibration = body;
  performance.sequence.labels.assign(frames.size(), Labels{});
  performance.sequence.frames = std::move(frames);
  return performance;
}

}  // namespace deixis::capture
