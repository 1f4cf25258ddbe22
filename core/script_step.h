#pragma once
// One step of a scripted person's performance (a site's virtual user, docs/site-config.md): what
// they do, at which target, and how long they stay after arriving; and when a performed step
// reached its completion state. Plain data, so the site configuration (site/) parses it, the
// capture (capture/virtual_user.h) performs it and a site reports on it, none depending on the
// others' code.

#include <string>
#include <string_view>

#include <cstddef>

#include "core/tracking.h"

namespace deixis {

// A person a script names by site name (`"person": "B"`) is not known until the run: who is in
// the room, under which PersonId, on which avatar spot. While the script is performed, the k-th
// distinct person it names (k = 0, 1, …, in order of first mention) is target
// script_person_target(k), below kNoTarget so that it is never an object or a person of the wire;
// the run replaces it with person_target of whoever of that site is there
// (site/remote_people.h, resolve_script_people).
constexpr TargetId script_person_target(std::size_t k) {
  return kNoTarget - 1 - static_cast<TargetId>(k);
}
constexpr bool is_script_person_target(TargetId id) {
  return id < kNoTarget;
}
constexpr std::size_t script_person_index(TargetId id) {
  return static_cast<std::size_t>(kNoTarget - 1 - id);
}

struct ScriptStep {
  enum class Action { kLookAt, kPoint, kTouch, kExplain, kRest };
  Action action = Action::kRest;
  // kLookAt, kPoint, kTouch: an object id, or 0 for the partner; kLookAt and kPoint at a person
  // named by site: script_person_target(k) (then `person` names them).
  TargetId target = kNoTarget;
  float seconds = 1.0f;  // how long to stay (hold, explain, rest) after arriving
  std::string person{};  // kLookAt, kPoint: the site name of the person, else empty
};

struct StepTiming {
  std::size_t step = 0;  // index into the script
  int cycle = 0;         // which repetition of the script
  ScriptStep::Action action = ScriptStep::Action::kRest;
  TargetId target = kNoTarget;
  double start = 0.0;     // s: the step begins
  double complete = 0.0;  // s: its completion state (gaze settled, reach complete, upright,
                          // last free-form stroke ended)
  double end = 0.0;       // s: complete + the step's seconds
};

// "look_at", "point", "touch", "explain", "rest" (the names of the site file).
constexpr std::string_view action_name(ScriptStep::Action action) {
  switch (action) {
    case ScriptStep::Action::kLookAt:
      return "look_at";
    case ScriptStep::Action::kPoint:
      return "point";
    case ScriptStep::Action::kTouch:
      return "touch";
    case ScriptStep::Action::kExplain:
      return "explain";
    case ScriptStep::Action::kRest:
      return "rest";
  }
  return "?";
}

}  // namespace deixis
