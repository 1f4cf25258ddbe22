// XR_EXT_hand_tracking: the 26 joints of each scripted hand. The wrist (and palm) are the script's
// wrist pose and the index tip its fingertip; the other joints lie on the segment between them,
// with the wrist's orientation, so an application reading any joint gets a plausible hand.

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

XrResult XRAPI_CALL CreateHandTrackerEXT(XrSession session, const XrHandTrackerCreateInfoEXT* info,
                                         XrHandTrackerEXT* tracker) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!rt.instance_live || rt.session == 0 || from_handle(session) != rt.session) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || tracker == nullptr || info->type != XR_TYPE_HAND_TRACKER_CREATE_INFO_EXT ||
      (info->hand != XR_HAND_LEFT_EXT && info->hand != XR_HAND_RIGHT_EXT)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->handJointSet != XR_HAND_JOINT_SET_DEFAULT_EXT) {
    return XR_ERROR_FEATURE_UNSUPPORTED;
  }
  const std::uint64_t id = rt.new_handle();
  rt.hand_trackers[id] = info->hand;
  rt.record.interaction = "hand_tracking";
  *tracker = to_handle<XrHandTrackerEXT>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroyHandTrackerEXT(XrHandTrackerEXT tracker) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  return rt.hand_trackers.erase(from_handle(tracker)) == 1 ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}

XrResult XRAPI_CALL LocateHandJointsEXT(XrHandTrackerEXT tracker,
                                        const XrHandJointsLocateInfoEXT* info,
                                        XrHandJointLocationsEXT* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.hand_trackers.find(from_handle(tracker));
  if (it == rt.hand_trackers.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || out == nullptr || info->type != XR_TYPE_HAND_JOINTS_LOCATE_INFO_EXT ||
      out->type != XR_TYPE_HAND_JOINT_LOCATIONS_EXT || out->jointLocations == nullptr ||
      out->jointCount != XR_HAND_JOINT_COUNT_EXT) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->time <= 0) {
    return XR_ERROR_TIME_INVALID;
  }
  const auto base = rt.spaces.find(from_handle(info->baseSpace));
  if (base == rt.spaces.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  out->isActive = XR_FALSE;
  for (uint32_t j = 0; j < out->jointCount; ++j) {
    out->jointLocations[j] = {0, {{0, 0, 0, 1}, {0, 0, 0}}, 0.01f};
  }
  const ScriptHand hand = rt.sample(info->time).hands[it->second == XR_HAND_LEFT_EXT ? 0 : 1];
  ScriptPose T_stage_base;
  const SpaceObject& b = base->second;
  if (!hand.tracked || b.is_action) {
    return XR_SUCCESS;  // hands are located in reference spaces only
  }
  T_stage_base =
      b.reference == XR_REFERENCE_SPACE_TYPE_VIEW ? rt.sample(info->time).head : ScriptPose{};
  T_stage_base = compose(T_stage_base, from_xr(b.pose_in_space));
  const ScriptPose T_base_stage = inverse(T_stage_base);
  for (uint32_t j = 0; j < out->jointCount; ++j) {
    ScriptPose joint = hand.wrist;
    if (j >= XR_HAND_JOINT_INDEX_METACARPAL_EXT && j <= XR_HAND_JOINT_INDEX_TIP_EXT) {
      const float s = static_cast<float>(j - XR_HAND_JOINT_INDEX_METACARPAL_EXT + 1) / 5.0f;
      joint.position = hand.wrist.position + s * (hand.index_tip - hand.wrist.position);
    } else if (j > XR_HAND_JOINT_WRIST_EXT) {
      joint.position = hand.wrist.position + 0.5f * (hand.index_tip - hand.wrist.position);
    }
    out->jointLocations[j].pose = to_xr(compose(T_base_stage, joint));
    out->jointLocations[j].locationFlags =
        XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT |
        XR_SPACE_LOCATION_POSITION_TRACKED_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
  }
  out->isActive = XR_TRUE;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
