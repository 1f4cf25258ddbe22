#pragma once
// A site's scripted person (docs/site-config.md, "virtual_user"): a capture subject standing at
// the site's floor placement performs the site's script (look at, point, touch, explain, rest)
// in that room, with the other person's avatar (target 0) where this room shows it, and the
// people it names by site where their avatars are expected to stand. The result is
// what a headset would report, a 30 Hz Sequence with exact labels, plus when each step reached
// its completion state, so a run can measure there.
//
// The same subject, room, script and seed give the same performance. The script may be repeated
// until a minimum duration is covered (a demo that runs longer than its script).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "capture/sequence.h"
#include "capture/subject.h"
#include "core/script_step.h"

namespace deixis::capture {

// A person the script names by site (`"person": "B"`): their target while performing
// (script_person_target(k), core/script_step.h) and where their avatar's eyes are in this room
// (the spot the site expects them on).
struct ScenePerson {
  std::string site;
  TargetId target = kNoTarget;
  Vec3 head = Vec3::Zero();
};

struct VirtualUserScene {
  Pose T_world_floor;  // where the person stands: a floor point, yaw only (0 faces −Z)
  std::span<const TargetObject> objects;  // the room's objects (ids ≥ 1)
  Vec3 partner_head = Vec3::Zero();       // target 0: the other person's (avatar's) eyes
  std::span<const ScenePerson> people{};  // the people the script looks and points at
};

struct ScriptPerformance {
  Sequence sequence;  // frames[i].time = i / 30; targets: the room's objects and the partner
  std::vector<StepTiming> steps;
};

// Performs `script` (1 or more steps) by `subject`, at least once and repeated until
// `min_seconds` is covered. Throws deixis::Error naming the step when it cannot be performed
// (an unknown target or person, a touch target out of reach from where the person stands).
ScriptPerformance perform_script(const Subject& subject, std::span<const ScriptStep> script,
                                 const VirtualUserScene& scene, std::uint64_t seed,
                                 double min_seconds = 0.0);

// A performance nobody scripted: a recording a site plays (docs/bvh.md#driving-a-site), with its
// body and frames; no labels beyond zeros (it designates nothing) and no steps.
ScriptPerformance unscripted_performance(const BodyCalibration& body,
                                         std::vector<TrackingFrame> frames);

}  // namespace deixis::capture
