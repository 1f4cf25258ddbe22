#pragma once
// Body turn (docs/decisions.md §73): the networks were trained on targets in front of the body
// (the capture's targets stand within about ±90° of the person's facing), so where this room's
// copy of a target stands behind the spot an avatar was placed on, its pointing and gaze end far
// off (a third person's avatar pointing 95–140° wide in the three-room demo). A person asked to
// point at something behind them turns their body first; the avatar does the same: while the
// person designates a target (the translator's head and hand blend weights), the avatar's root
// turns about the vertical, at a bounded speed, until this room's copy stands within
// `comfort_deg` of its facing, and turns back to the spot's facing as the gesture ends. The
// networks see the turned root (the avatar's pose is root-relative), so the whole body turns
// with it, and every target in front of the spot leaves the avatar where the site placed it.

#include "core/math/pose.h"
#include "core/target_map.h"

namespace deixis::presence {

struct BodyTurnConfig {
  // Targets within this azimuth of the facing need no turn; one further out is brought to it.
  // The hand points across the front of the body; the head and eyes alone reach further round
  // (a person looks at someone 60° to their side without turning: the networks do too, within
  // the few degrees gaze settling finishes), so a gaze turns the body only past `gaze_comfort_deg`.
  float comfort_deg = 45.0f;
  float gaze_comfort_deg = 80.0f;
  float max_turn_deg = 135.0f;  // the furthest the body turns from the spot's facing
  float speed_deg_per_s = 150.0f;
};

// The yaw (rad, + to the left) the body wants for a target at `target` (world; null: none),
// seen from `T_world_spot` (the spot's origin: position and facing, yaw only), while the person
// designates with weight `weight` (0: nothing designated, the spot's facing; 1: fully), with
// the hand (`pointing`) or with the eyes alone.
float wanted_turn(const Pose& T_world_spot, const Vec3* target, float weight, bool pointing,
                  const BodyTurnConfig& config = {});

// What the body turns for this tick: the target, the weight of its designation and whether the
// hand designates it (the pointing comfort) or the eyes alone.
struct TurnDesignation {
  const Vec3* target = nullptr;
  float weight = 0.0f;
  bool pointing = false;
};

// From last tick's designation: the hand's target (null: none) with MPNet's deictic progression,
// the eyes' with the gaze progression. The hand's rules while its progression is at least the
// gaze's, and always when both designate the same target: a person looks at what they point
// at, and the two progressions end their holds a tick apart, so choosing by which is larger
// alone turned the body back to the eyes' comfort and forth again mid-gesture (docs/decisions.md
// §82). The body has turned all the way by the gesture's middle (weight twice the progression).
TurnDesignation turn_designation(const Vec3* hand, TargetId hand_target, float deictic,
                                 const Vec3* head, TargetId head_target, float gaze);

// `current` moved toward `wanted` by at most the config's speed over `dt` seconds.
float turned(float current, float wanted, float dt, const BodyTurnConfig& config = {});

}  // namespace deixis::presence
