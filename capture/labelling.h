#pragma once
// The progression labels of paper §III.B, written by the script as it plans each movement, so
// they are exact: gaze rises from 0 at the onset of a gaze shift toward the head target to 1 when
// eyes and head have settled on it; deictic rises from 0 at the onset of a reach toward the hand
// target to 1 at the completion state; both fall linearly while leaving. Idle is 1 in the upright
// posture and 0 out of it: it falls linearly from the first movement's onset until the person is
// out of the upright posture (the deictic hand 0.25 m from its rest position, the paper's own
// threshold for the distance feature d), and rises back to 1 over the 0.5 s after the person is
// upright again. The head and hand targets change at the onset of the movement toward the new
// target. Every ramp's start and end is a phase key (the authors' key rows,
// docs/dataset.md#tensors).

#include <algorithm>
#include <functional>
#include <vector>

#include "capture/timeline.h"
#include "core/tracking.h"

namespace deixis::capture {

inline constexpr double kIdleDelay = 0.5;  // s back in the upright posture before idle = 1

struct Labelling {
  Ramp gaze{0.0f};
  Ramp deictic{0.0f};
  std::vector<double> rest_exits;    // onsets of movement out of the upright posture
  std::vector<double> rest_returns;  // when the person is upright again
  Steps<TargetId> head_target{kNoTarget};
  Steps<TargetId> hand_target{kNoTarget};
  std::vector<double> phase_keys;

  // A progression toward a new target: 0 from the moment it becomes the target, rising linearly
  // from the movement's onset to 1 at `complete`.
  void begin(Ramp& ramp, double target_switch, double onset, double complete) {
    ramp.to(target_switch, 0.0, 0.0f);
    ramp.to(onset, complete - onset, 1.0f);
    phase_keys.push_back(onset);
    phase_keys.push_back(complete);
  }
  // Leaving a completed progression: falls linearly from `start` to 0 at `end`.
  void end(Ramp& ramp, double start, double end_time) {
    if (ramp.last() > 0.0f) {
      ramp.to(start, end_time - start, 0.0f);
      phase_keys.push_back(start);
      phase_keys.push_back(end_time);
    }
  }
  // The first movement out of the upright posture.
  void leave_rest(double onset) {
    if (rest_exits.size() == rest_returns.size()) {
      rest_exits.push_back(onset);
    }
  }
  // Upright again at `upright`: idle rises to 1 over the next 0.5 s.
  void back_at_rest(double upright) {
    if (rest_exits.size() > rest_returns.size()) {
      rest_returns.push_back(upright);
    }
  }
  // The idle course, given when the person is out of the upright posture after each exit's onset
  // (found from the motion, which the labeller watches). Adds the idle phase keys.
  Ramp idle_course(const std::function<double(double)>& out_of_posture) {
    Ramp idle(1.0f);
    for (std::size_t i = 0; i < rest_exits.size(); ++i) {
      const double onset = rest_exits[i];
      const double away = std::max(out_of_posture(onset), onset);
      idle.to(onset, away - onset, 0.0f);
      phase_keys.push_back(onset);
      phase_keys.push_back(away);
      if (i < rest_returns.size()) {
        idle.to(rest_returns[i], kIdleDelay, 1.0f);
        phase_keys.push_back(rest_returns[i]);
        phase_keys.push_back(rest_returns[i] + kIdleDelay);
      }
    }
    return idle;
  }
};

}  // namespace deixis::capture
