#pragma once
// Random targets around a recorded person (stance frame, then the world): pointing targets
// 0.3–5 m from the eyes within ±75° of azimuth and the rules' elevations, touch targets within
// reach (checked with the same torso plan the touch will use), and the other person (id 0,
// core/target_map.h) as the listener of the explanation categories. Successive targets of one
// sequence are kept apart so that a change of target is a real gesture.

#include <vector>

#include "capture/motion.h"
#include "core/target_map.h"

namespace deixis::capture {

// Where pointing targets may stand, as elevation from the eyes (degrees, positive up). The
// defaults are the first captures' rules, which every set keeps for its sequences 0..count−1, so
// the held-out tables compare across versions and the training set contains the one the shipped
// weights came from.
struct TargetRules {
  float pointing_elevation_min_deg = -25.0f;
  float pointing_elevation_max_deg = 30.0f;
};

// The rules of the pointing sequences the training set adds after those (capture/generate.h
// low_target_count): targets 25° to 50° below the eyes. A person in a room points at low, near
// things (a table beside the other person), which the first training set never showed the
// networks (docs/decisions.md 87 and 89, docs/live-rooms.md).
TargetRules low_target_rules();

class TargetSampler {
 public:
  TargetSampler(const Motion& motion, Random& rng, const TargetRules& rules = {});

  // Each new target is at least `min_separation` (rad, seen from the eyes) from `others`.
  TargetObject pointing(TargetId id, const std::vector<TargetObject>& others);
  TargetObject touching(TargetId id, const std::vector<TargetObject>& others);
  TargetObject partner(const std::vector<TargetObject>& others);

  static constexpr float kMinSeparation = 0.35f;  // 20°

 private:
  Vec3 eyes() const;
  Vec3 in_world(const Vec3& p_stance) const;
  bool apart(const Vec3& p, const std::vector<TargetObject>& others) const;

  const Motion& motion_;
  Random& rng_;
  TargetRules rules_;
};

}  // namespace deixis::capture
