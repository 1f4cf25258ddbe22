#pragma once
// Two-bone IK (shoulder–elbow–wrist), in the style of ozz-animation's IKTwoBoneJob: public
// inputs, caller-owned outputs, validate() with a reason, run() that never allocates.
//
// The job computes rotations for the start (upper arm) and mid (lower arm) joints so that the end
// joint (wrist) lands on `target`, with the mid joint bent toward `pole_vector`. Both bones are
// oriented from frames (bone direction, hinge axis), so the upper arm's twist always matches the
// elbow's hinge plane, whatever pose the chain starts from. Near full reach the chain is softened
// (it falls gradually behind the target instead of snapping straight); flexion limits bound the
// distance from both sides. Targets that cannot be reached are approached along the ray from the
// start joint, so an arm that cannot reach still points at its target.

#include <string_view>

#include "ik/joint_limits.h"

namespace deixis::ik {

// Shortest and longest start→end distances of a chain with bones a and b whose mid joint flexes
// within `flexion` (0 = straight).
struct Reach {
  float min;
  float max;
};
Reach reach_of(float a, float b, const HingeRange& flexion);

// The distance a softened chain actually reaches for a target at distance d: d itself up to
// `soft_start`, then an exponential approach to `max` (C1 at soft_start, never beyond max).
float soft_reach(float d, float soft_start, float max);

struct TwoBoneJob {
  // True when run() can run; otherwise false, and *reason (if given) names the broken rule.
  bool validate(std::string_view* reason = nullptr) const;
  // Validates, then computes the corrections. Returns false (outputs untouched) when invalid.
  bool run() const;

  // ---- inputs ----
  // Model-space poses (T_model_joint) of the chain. The joints must be ancestors of one another
  // but need not be direct parents (joints in between stay fixed).
  const Pose* start_joint = nullptr;
  const Pose* mid_joint = nullptr;
  const Pose* end_joint = nullptr;
  Vec3 target = Vec3::Zero();             // model space; non-finite: no correction
  Vec3 pole_vector = Vec3::UnitY();       // model space; the mid joint bends toward it
  Vec3 mid_axis = Vec3::UnitZ();          // unit hinge axis in the mid joint's frame: a positive
                                          // rotation about it flexes the chain
  float soften = 1.0f;                    // (0, 1]: fraction of the max reach where softening
                                          // starts; 1 = none
  HingeRange flexion{0.0f, deg(145.0f)};  // allowed flexion of the mid joint, within [0, π]

  // ---- outputs ----
  // Local-space corrections, to be post-multiplied onto the joints' local rotations
  // (local' = local · correction), in that order: start first, then mid.
  Mat3* start_correction = nullptr;
  Mat3* mid_correction = nullptr;
  bool* reached = nullptr;       // optional: the end lands on the target (within 0.1 mm)
  Vec3* end_position = nullptr;  // optional: where the end joint lands, model space
};

}  // namespace deixis::ik
