#pragma once
// One step of a scripted person's performance (a site's virtual user, docs/site-config.md): what
// they do, at which target, and how long they stay after arriving. Plain data, so the site
// configuration (app/) can parse it and the capture can perform it without either depending on
// the other's code.

#include <string_view>

#include "gesture/tracking.h"

namespace deixis::capture {

struct ScriptStep {
  enum class Action { kLookAt, kPoint, kTouch, kExplain, kRest };
  Action action = Action::kRest;
  TargetId target = kNoTarget;  // kLookAt, kPoint, kTouch: an object id, or 0 for the partner
  float seconds = 1.0f;         // how long to stay (hold, explain, rest) after arriving
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

}  // namespace deixis::capture
