#include "xr/input.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "xr/xr_struct.h"

namespace deixis::xr {

namespace {

constexpr XrSpaceLocationFlags kPoseValid =
    XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT;

XrAction create_action(XrInstance xi, XrActionSet set, XrActionType type, const char* name,
                       const char* localized, const XrPath* subactions, std::uint32_t n) {
  auto ci = make<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
  std::snprintf(ci.actionName, XR_MAX_ACTION_NAME_SIZE, "%s", name);
  std::snprintf(ci.localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE, "%s", localized);
  ci.actionType = type;
  ci.countSubactionPaths = n;
  ci.subactionPaths = subactions;
  XrAction action = XR_NULL_HANDLE;
  XR_CHECK(xi, xrCreateAction(set, &ci, &action));
  return action;
}

XrAction create_pose_action(XrInstance xi, XrActionSet set, const char* name, const char* localized,
                            const XrPath* subactions, std::uint32_t n) {
  return create_action(xi, set, XR_ACTION_TYPE_POSE_INPUT, name, localized, subactions, n);
}

XrSpace action_space(XrInstance xi, XrSession session, XrAction action, XrPath subaction) {
  auto ci = make<XrActionSpaceCreateInfo>(XR_TYPE_ACTION_SPACE_CREATE_INFO);
  ci.action = action;
  ci.subactionPath = subaction;
  ci.poseInActionSpace.orientation.w = 1.0f;
  XrSpace space = XR_NULL_HANDLE;
  XR_CHECK(xi, xrCreateActionSpace(session, &ci, &space));
  return space;
}

void suggest(const Instance& instance, const char* profile,
             std::initializer_list<std::pair<XrAction, const char*>> bindings) {
  std::array<XrActionSuggestedBinding, 8> list{};
  std::uint32_t n = 0;
  for (const auto& [action, path] : bindings) {
    list[n++] = {action, instance.path(path)};
  }
  auto sb =
      make<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
  sb.interactionProfile = instance.path(profile);
  sb.countSuggestedBindings = n;
  sb.suggestedBindings = list.data();
  XR_CHECK(instance.handle(), xrSuggestInteractionProfileBindings(instance.handle(), &sb));
}

}  // namespace

std::optional<Pose> to_pose(const XrPosef& p) {
  const float values[] = {p.position.x,    p.position.y,    p.position.z,   p.orientation.x,
                          p.orientation.y, p.orientation.z, p.orientation.w};
  for (const float v : values) {
    if (!std::isfinite(v)) {
      return std::nullopt;
    }
  }
  const Quat q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  if (std::abs(q.norm() - 1.0f) > 1e-2f) {
    return std::nullopt;
  }
  return Pose{q.normalized().toRotationMatrix(), Vec3(p.position.x, p.position.y, p.position.z)};
}

Pose wrist_from_joint(const Pose& T_world_joint, Hand hand) {
  // Columns: the Deixis wrist axes in the joint frame.
  Mat3 R_joint_wrist;
  if (hand == Hand::kRight) {
    R_joint_wrist << 0, 0, 1,  //
        0, 1, 0,               //
        -1, 0, 0;              // x = −Z, y = +Y, z = +X
  } else {
    R_joint_wrist << 0, 0, -1,  //
        0, 1, 0,                //
        1, 0, 0;                // x = +Z, y = +Y, z = −X
  }
  return {T_world_joint.rotation * R_joint_wrist, T_world_joint.translation};
}

bool pose_valid(XrSpaceLocationFlags flags) {
  return (flags & kPoseValid) == kPoseValid;
}

Input::Input(const Instance& instance, const GlSession& session)
    : instance_(instance.handle()),
      session_(session.handle()),
      stage_(session.stage()),
      view_(session.view()) {
  const XrInstance xi = instance_;
  hand_paths_ = {instance.path("/user/hand/left"), instance.path("/user/hand/right")};
  auto sci = make<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
  std::snprintf(sci.actionSetName, XR_MAX_ACTION_SET_NAME_SIZE, "%s", "deixis");
  std::snprintf(sci.localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE, "%s", "Deixis");
  XR_CHECK(xi, xrCreateActionSet(xi, &sci, &set_));
  try {
    grip_action_ = create_pose_action(xi, set_, "hand_grip", "Hand grip", hand_paths_.data(), 2);
    aim_action_ = create_pose_action(xi, set_, "hand_aim", "Hand aim", hand_paths_.data(), 2);
    select_action_ = create_action(xi, set_, XR_ACTION_TYPE_BOOLEAN_INPUT, "select", "Select",
                                   hand_paths_.data(), 2);
    menu_action_ = create_action(xi, set_, XR_ACTION_TYPE_BOOLEAN_INPUT, "menu", "Menu",
                                 hand_paths_.data(), 2);
    suggest(instance, "/interaction_profiles/khr/simple_controller",
            {{grip_action_, "/user/hand/left/input/grip/pose"},
             {grip_action_, "/user/hand/right/input/grip/pose"},
             {aim_action_, "/user/hand/left/input/aim/pose"},
             {aim_action_, "/user/hand/right/input/aim/pose"},
             {select_action_, "/user/hand/left/input/select/click"},
             {select_action_, "/user/hand/right/input/select/click"},
             {menu_action_, "/user/hand/left/input/menu/click"},
             {menu_action_, "/user/hand/right/input/menu/click"}});
    if (instance.features().eye_gaze) {
      gaze_action_ = create_pose_action(xi, set_, "eye_gaze", "Eye gaze", nullptr, 0);
      suggest(instance, "/interaction_profiles/ext/eye_gaze_interaction",
              {{gaze_action_, "/user/eyes_ext/input/gaze_ext/pose"}});
    }
    auto ai = make<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
    ai.countActionSets = 1;
    ai.actionSets = &set_;
    XR_CHECK(xi, xrAttachSessionActionSets(session_, &ai));
    for (int h = 0; h < 2; ++h) {
      const auto i = static_cast<std::size_t>(h);
      grip_spaces_[i] = action_space(xi, session_, grip_action_, hand_paths_[i]);
      aim_spaces_[i] = action_space(xi, session_, aim_action_, hand_paths_[i]);
    }
    if (gaze_action_ != XR_NULL_HANDLE) {
      gaze_space_ = action_space(xi, session_, gaze_action_, XR_NULL_PATH);
    }
    if (instance.features().hand_tracking) {
      const auto create = instance.function<PFN_xrCreateHandTrackerEXT>("xrCreateHandTrackerEXT");
      destroy_tracker_ = instance.function<PFN_xrDestroyHandTrackerEXT>("xrDestroyHandTrackerEXT");
      locate_joints_ = instance.function<PFN_xrLocateHandJointsEXT>("xrLocateHandJointsEXT");
      for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
        auto ci = make<XrHandTrackerCreateInfoEXT>(XR_TYPE_HAND_TRACKER_CREATE_INFO_EXT);
        ci.hand = hand == Hand::kLeft ? XR_HAND_LEFT_EXT : XR_HAND_RIGHT_EXT;
        ci.handJointSet = XR_HAND_JOINT_SET_DEFAULT_EXT;
        XR_CHECK(xi, create(session_, &ci, &hand_trackers_[static_cast<std::size_t>(index(hand))]));
      }
    }
  } catch (...) {
    for (XrHandTrackerEXT t : hand_trackers_) {
      if (t != XR_NULL_HANDLE) {
        destroy_tracker_(t);
      }
    }
    xrDestroyActionSet(set_);  // destroys its actions; the session destroys the spaces
    throw;
  }
}

Input::~Input() {
  for (XrHandTrackerEXT t : hand_trackers_) {
    if (t != XR_NULL_HANDLE) {
      destroy_tracker_(t);
    }
  }
  for (XrSpace s :
       {gaze_space_, grip_spaces_[0], grip_spaces_[1], aim_spaces_[0], aim_spaces_[1]}) {
    if (s != XR_NULL_HANDLE) {
      xrDestroySpace(s);
    }
  }
  xrDestroyActionSet(set_);
}

void Input::sync() {
  buttons_ = {};  // unfocused: nothing held, nothing pressed
  XrActiveActionSet active{set_, XR_NULL_PATH};
  auto si = make<XrActionsSyncInfo>(XR_TYPE_ACTIONS_SYNC_INFO);
  si.countActiveActionSets = 1;
  si.activeActionSets = &active;
  const XrResult r = xrSyncActions(session_, &si);
  if (r == XR_SESSION_NOT_FOCUSED) {
    return;  // a qualified success: no input this frame
  }
  XR_CHECK(instance_, r);
  synced_ = true;
  read_buttons();
}

// Pressed: the state changed to down in this sync (spec §11.5: changedSinceLastSync).
bool Input::read_button(XrAction action, std::size_t hand, bool& pressed) const {
  auto gi = make<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
  gi.action = action;
  gi.subactionPath = hand_paths_[hand];
  auto state = make<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
  XR_CHECK(instance_, xrGetActionStateBoolean(session_, &gi, &state));
  const bool down = state.isActive == XR_TRUE && state.currentState == XR_TRUE;
  pressed = down && state.changedSinceLastSync == XR_TRUE;
  return down;
}

void Input::read_buttons() {
  for (std::size_t h = 0; h < 2; ++h) {
    buttons_.select[h] = read_button(select_action_, h, buttons_.select_pressed[h]);
    buttons_.menu[h] = read_button(menu_action_, h, buttons_.menu_pressed[h]);
  }
}

bool Input::locate_space(XrSpace space, XrTime time, Pose& out) const {
  auto location = make<XrSpaceLocation>(XR_TYPE_SPACE_LOCATION);
  XR_CHECK(instance_, xrLocateSpace(space, stage_, time, &location));
  if (!pose_valid(location.locationFlags)) {
    return false;
  }
  const std::optional<Pose> pose = to_pose(location.pose);
  if (!pose) {
    return false;
  }
  out = *pose;
  return true;
}

bool Input::locate_hand_joints(Hand hand, XrTime time, TrackingFrame& frame) {
  auto li = make<XrHandJointsLocateInfoEXT>(XR_TYPE_HAND_JOINTS_LOCATE_INFO_EXT);
  li.baseSpace = stage_;
  li.time = time;
  auto locations = make<XrHandJointLocationsEXT>(XR_TYPE_HAND_JOINT_LOCATIONS_EXT);
  locations.jointCount = XR_HAND_JOINT_COUNT_EXT;
  locations.jointLocations = joints_.data();
  XR_CHECK(instance_,
           locate_joints_(hand_trackers_[static_cast<std::size_t>(index(hand))], &li, &locations));
  if (locations.isActive != XR_TRUE) {
    return false;
  }
  const XrHandJointLocationEXT& wrist = joints_[XR_HAND_JOINT_WRIST_EXT];
  const XrHandJointLocationEXT& tip = joints_[XR_HAND_JOINT_INDEX_TIP_EXT];
  if (!pose_valid(wrist.locationFlags) ||
      (tip.locationFlags & XR_SPACE_LOCATION_POSITION_VALID_BIT) == 0) {
    return false;
  }
  const std::optional<Pose> w = to_pose(wrist.pose);
  const Vec3 t(tip.pose.position.x, tip.pose.position.y, tip.pose.position.z);
  if (!w || !t.allFinite()) {
    return false;
  }
  const auto i = static_cast<std::size_t>(index(hand));
  frame.T_world_wrist[i] = wrist_from_joint(*w, hand);
  frame.index_tip[i] = t;
  return true;
}

bool Input::locate_controller(Hand hand, XrTime time, TrackingFrame& frame) {
  if (!synced_) {
    return false;
  }
  const auto i = static_cast<std::size_t>(index(hand));
  auto gi = make<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
  gi.action = grip_action_;
  gi.subactionPath = hand_paths_[i];
  auto state = make<XrActionStatePose>(XR_TYPE_ACTION_STATE_POSE);
  XR_CHECK(instance_, xrGetActionStatePose(session_, &gi, &state));
  if (state.isActive != XR_TRUE) {
    return false;
  }
  Pose grip;
  Pose aim;
  if (!locate_space(grip_spaces_[i], time, grip) || !locate_space(aim_spaces_[i], time, aim)) {
    return false;
  }
  frame.T_world_wrist[i] = wrist_from_joint(grip, hand);
  frame.index_tip[i] = aim.translation;
  return true;
}

// The gaze action is only known once actions are synced (with focus); before that no gaze is
// given, as for the controllers. Without eye gaze the caller estimates it from the head.
bool Input::locate_eye_gaze(XrTime time, TrackingFrame& frame) {
  auto gi = make<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
  gi.action = gaze_action_;
  auto state = make<XrActionStatePose>(XR_TYPE_ACTION_STATE_POSE);
  XR_CHECK(instance_, xrGetActionStatePose(session_, &gi, &state));
  Pose gaze;
  if (state.isActive != XR_TRUE || !locate_space(gaze_space_, time, gaze)) {
    return false;
  }
  frame.gaze = -gaze.rotation.col(2);
  frame.valid |= tracked::kGaze;
  return true;
}

TrackingFrame Input::locate(XrTime time, double clock) {
  TrackingFrame frame;
  frame.time = clock;
  if (locate_space(view_, time, frame.T_world_head)) {
    frame.valid |= tracked::kHead;
  }
  const bool eyes_known = gaze_space_ != XR_NULL_HANDLE && synced_;
  const bool eyes = eyes_known && locate_eye_gaze(time, frame);
  // No eye tracking (or eyes not tracked now): the head's forward, estimated (decision 79).
  if (!eyes && (eyes_known || gaze_space_ == XR_NULL_HANDLE) &&
      (frame.valid & tracked::kHead) != 0) {
    frame.gaze = -frame.T_world_head.rotation.col(2);
    frame.valid |= tracked::kGaze;
    ++gaze_from_head_frames_;
  }
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    const bool ok = hand_tracking() ? locate_hand_joints(hand, time, frame)
                                    : locate_controller(hand, time, frame);
    if (ok) {
      frame.valid |= tracked::hand(hand);
    }
  }
  return frame;
}

}  // namespace deixis::xr
