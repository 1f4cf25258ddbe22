#pragma once
// Setting up a room's target map from inside the headset (`deixis xr --setup`, docs/xr.md
// "Setting up the room", decision 85): the user puts each of the map's objects on the real
// object it stands for, by touching it or by pointing at it from two places, moves and resizes
// it, and the map is saved for later sessions. The objects are the map's own (ids correspond
// across rooms, docs/target-map.md), taken one after another; nothing is added or removed here.
//
// Tools, used with the deictic hand's act control (select); another control changes the tool,
// another the object:
// - touch: act with the fingertip outside the object puts it there, its near surface (as seen
//   from the eyes) at the fingertip; with the fingertip inside (or within kGrabMarginM of its
//   surface) it grabs it. While held, the object follows the fingertip; it lands on release.
// - point: act marks the eye–fingertip ray (the ray people aim along, gesture/target_selection.h).
//   A second ray from at least kMinBaselineM away that passes within kMaxMissM of the first puts
//   the object's centre midway between the rays' closest points (triangulation: a headset without
//   depth sensing knows no surface the ray could hit).
// - resize: while act is held the object's size scales with the fingertip's distance from its
//   centre against the distance when act went down (kMinSizeM–kMaxSizeM per axis).
//
// Pure logic over tracking and control edges: no rendering, no files, no allocation per frame.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "core/target_map.h"
#include "core/tracking.h"

namespace deixis::site {

enum class SetupTool { kTouch, kPoint, kResize };
std::string_view setup_tool_name(SetupTool tool);

// This frame's controls, as `deixis xr` maps the controllers' buttons (xr/input.h Buttons).
struct SetupControls {
  bool act = false;          // held
  bool act_pressed = false;  // went down this frame
  bool next_tool = false;    // pressed this frame
  bool next_object = false;  // pressed this frame
};

// A ray marked by pointing, waiting for its second.
struct SetupRay {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3(0, 0, -1);  // unit
};

class RoomSetup {
 public:
  static constexpr float kGrabMarginM = 0.05f;
  static constexpr float kMinBaselineM = 0.3f;
  static constexpr float kMaxMissM = 0.15f;
  static constexpr float kMinRayAngleDeg = 5.0f;
  static constexpr float kMinSizeM = 0.02f;
  static constexpr float kMaxSizeM = 10.0f;

  // Throws deixis::Error when the map has no objects to set up (naming `source`).
  RoomSetup(TargetMap map, Hand hand, std::string_view source);

  // One frame of the user's tracking and controls. True when an edit was completed (an object
  // placed, moved or resized): the caller saves the map.
  bool update(const TrackingFrame& user, const SetupControls& controls);

  const TargetMap& map() const { return map_; }
  const TargetObject& current() const { return map_.objects[current_]; }
  std::size_t current_index() const { return current_; }
  SetupTool tool() const { return tool_; }
  bool holding() const { return hold_ != Hold::kNone; }
  const std::optional<SetupRay>& first_ray() const { return first_ray_; }
  // What the user is told now (one line, e.g. "point at Jupiter from a second place"); changes
  // only on an event, so a panel can rebuild its text only then.
  const std::string& message() const { return message_; }
  std::uint64_t edits() const { return edits_; }

 private:
  enum class Hold { kNone, kMove, kResize };
  bool hand_ready(const TrackingFrame& user) const;
  void press(const TrackingFrame& user);
  bool release();
  void follow(const TrackingFrame& user);
  bool mark_ray(const TrackingFrame& user);  // true: placed
  void tell(std::string message);
  void prompt();

  TargetMap map_;
  Hand hand_;
  std::size_t current_ = 0;
  SetupTool tool_ = SetupTool::kTouch;
  Hold hold_ = Hold::kNone;
  Vec3 grab_offset_ = Vec3::Zero();  // object centre − fingertip, while moving
  Vec3 size_at_press_ = Vec3::Zero();
  float reach_at_press_ = 0.0f;  // fingertip to centre when resizing began
  std::optional<SetupRay> first_ray_;
  std::string message_;
  std::uint64_t edits_ = 0;
};

// Where an object of `size` and `kind` must stand so that its surface is at `touched`, seen from
// `eye`: its centre beyond the touched point along the eye → touched ray by the object's extent
// in that direction (a sphere's radius, a box's half-extent through its side).
Vec3 centre_behind_touch(TargetKind kind, const Vec3& size, const Vec3& eye, const Vec3& touched);

// Triangulates two rays: the midpoint of their closest points and how far apart those are;
// nothing when the rays are within `min_angle_deg` of parallel or meet behind an origin.
struct RayMeeting {
  Vec3 point = Vec3::Zero();
  float miss_m = 0.0f;
};
std::optional<RayMeeting> triangulate(const SetupRay& a, const SetupRay& b, float min_angle_deg);

}  // namespace deixis::site
