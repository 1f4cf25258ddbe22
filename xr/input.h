#pragma once
// What the headset tells about its user, as the TrackingFrame the rest of Deixis reads
// (core/tracking.h): the head from the VIEW space, the eye gaze (XR_EXT_eye_gaze_interaction
// where offered), and per hand the wrist and index fingertip from XR_EXT_hand_tracking's joints
// where offered, else from the controllers' grip (wrist) and aim (fingertip) poses. Where the
// runtime has no eye gaze (no XR_EXT_eye_gaze_interaction, or the synced gaze action inactive)
// the gaze is estimated as the head's forward, as for recordings (docs/bvh.md, decision 79):
// the translator needs a gaze, and a head-mounted display's forward is where its user looks
// within the eyes' range. A part the
// runtime does not report as valid, or reports with a non-finite or non-unit value, is left out
// of the frame's validity flags.
//
// Wrist frames (docs/decisions.md §7; XR_EXT_hand_tracking joints: −Z towards the fingertips, +Y
// the back of the hand, +X = Y × Z): right hand Deixis x, y, z = joint −Z, +Y, +X; left hand
// +Z, +Y, −X.

#include <openxr/openxr.h>

#include <array>
#include <cstdint>
#include <optional>

#include "core/tracking.h"
#include "xr/gl_session.h"
#include "xr/instance.h"

namespace deixis::xr {

// An OpenXR pose as a Deixis pose; empty when any component is not finite or the quaternion is
// far from unit length.
std::optional<Pose> to_pose(const XrPosef& pose);
// A hand joint's (or grip's) frame as the Deixis wrist frame of that hand.
Pose wrist_from_joint(const Pose& T_world_joint, Hand hand);
// Both position and orientation flagged valid.
bool pose_valid(XrSpaceLocationFlags flags);

// The two buttons every controller has (khr/simple_controller: select and menu; a runtime maps
// its own controllers' onto them), per hand (index(Hand)): held after the last sync, and pressed
// (went down) in it. All false before the first sync with focus, and without focus.
struct Buttons {
  std::array<bool, 2> select{};
  std::array<bool, 2> menu{};
  std::array<bool, 2> select_pressed{};
  std::array<bool, 2> menu_pressed{};
};

class Input {
 public:
  // Creates the pose actions (gaze, grip, aim) and the button actions (select, menu), suggests
  // bindings for /interaction_profiles/khr/simple_controller and ext/eye_gaze_interaction,
  // attaches them, and creates a hand tracker per hand where hand tracking is supported. Throws
  // deixis::Error.
  Input(const Instance& instance, const GlSession& session);
  ~Input();
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;

  // xrSyncActions: once per frame, only with input focus (xr/session_state.h syncs_actions);
  // reads the buttons.
  void sync();
  // The buttons as of the last sync (pressed: in that sync only). Allocates nothing.
  const Buttons& buttons() const { return buttons_; }
  // The user at display time `time`, stamped `clock` (s). Allocates nothing.
  TrackingFrame locate(XrTime time, double clock);

  bool hand_tracking() const { return hand_trackers_[0] != XR_NULL_HANDLE; }
  bool eye_gaze() const { return gaze_action_ != XR_NULL_HANDLE; }
  // Frames whose gaze is the head's forward (estimated) rather than the eyes'.
  std::uint64_t gaze_from_head_frames() const { return gaze_from_head_frames_; }

 private:
  bool locate_hand_joints(Hand hand, XrTime time, TrackingFrame& frame);
  bool locate_controller(Hand hand, XrTime time, TrackingFrame& frame);
  bool locate_space(XrSpace space, XrTime time, Pose& out) const;
  bool locate_eye_gaze(XrTime time, TrackingFrame& frame);
  void read_buttons();
  bool read_button(XrAction action, std::size_t hand, bool& pressed) const;

  XrInstance instance_;
  XrSession session_;
  XrSpace stage_;
  XrSpace view_;
  XrActionSet set_ = XR_NULL_HANDLE;
  XrAction gaze_action_ = XR_NULL_HANDLE;
  XrAction grip_action_ = XR_NULL_HANDLE;
  XrAction aim_action_ = XR_NULL_HANDLE;
  XrAction select_action_ = XR_NULL_HANDLE;
  XrAction menu_action_ = XR_NULL_HANDLE;
  std::array<XrPath, 2> hand_paths_{};  // by Hand
  XrSpace gaze_space_ = XR_NULL_HANDLE;
  std::array<XrSpace, 2> grip_spaces_{};
  std::array<XrSpace, 2> aim_spaces_{};
  std::array<XrHandTrackerEXT, 2> hand_trackers_{};
  PFN_xrLocateHandJointsEXT locate_joints_ = nullptr;
  PFN_xrDestroyHandTrackerEXT destroy_tracker_ = nullptr;
  std::array<XrHandJointLocationEXT, XR_HAND_JOINT_COUNT_EXT> joints_{};
  bool synced_ = false;
  Buttons buttons_;
  std::uint64_t gaze_from_head_frames_ = 0;
};

}  // namespace deixis::xr
