// Reference spaces (STAGE: the floor origin; LOCAL: the same origin here; VIEW: the head), action
// spaces on pose actions, xrLocateSpace and xrLocateViews, all sampled from the script at the
// requested time.

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

constexpr XrFovf kFov{-0.80f, 0.80f, 0.80f, -0.80f};  // radians, each eye
constexpr float kStageExtent = 3.0f;                  // m: the stage is 3 m x 3 m

bool valid_session(const Runtime& rt, XrSession session) {
  return rt.instance_live && rt.session != 0 && from_handle(session) == rt.session;
}

// T_stage_space at `time`; false when the space is not tracked then.
bool locate_in_stage(const Runtime& rt, const SpaceObject& space, XrTime time, ScriptPose& out) {
  ScriptPose base;
  if (space.is_action) {
    const auto it = rt.actions.find(space.action);
    if (it == rt.actions.end() || !rt.session_state.actions_attached) {
      return false;
    }
    bool found = false;
    for (const ActionBinding& b : it->second.bindings) {
      if (b.component == kPose && (space.subaction == XR_NULL_PATH || space.subaction == b.user)) {
        found = locate_source(b.source, time, base);
        if (found) {
          break;
        }
      }
    }
    if (!found) {
      return false;
    }
  } else if (space.reference == XR_REFERENCE_SPACE_TYPE_VIEW) {
    base = rt.sample(time).head;
  }
  out = compose(base, from_xr(space.pose_in_space));
  return true;
}

}  // namespace

bool locate_source(Source source, XrTime time, ScriptPose& out) {
  const Runtime& rt = state();
  const ScriptSample s = rt.sample(time);
  switch (source) {
    case Source::kHead:
      out = s.head;
      return true;
    case Source::kGaze: {
      if (!rt.extension_enabled("XR_EXT_eye_gaze_interaction")) {
        return false;
      }
      // −Z along the gaze, +Y as close to the stage's up as the gaze allows.
      const Eigen::Vector3f back = -s.gaze;
      Eigen::Vector3f right = Eigen::Vector3f::UnitY().cross(back);
      if (right.norm() < 1e-4f) {
        right = Eigen::Vector3f::UnitX();
      }
      right.normalize();
      Eigen::Matrix3f m;
      m.col(0) = right;
      m.col(1) = back.cross(right);
      m.col(2) = back;
      out = {s.head.position, Eigen::Quaternionf(m)};
      return true;
    }
    case Source::kLeftGrip:
    case Source::kRightGrip:
    case Source::kLeftAim:
    case Source::kRightAim: {
      const bool left = source == Source::kLeftGrip || source == Source::kLeftAim;
      const ScriptHand& hand = s.hands[left ? 0 : 1];
      if (!hand.tracked) {
        return false;
      }
      out = hand.wrist;  // grip: the wrist; aim: at the index fingertip, the wrist's orientation
      if (source == Source::kLeftAim || source == Source::kRightAim) {
        out.position = hand.index_tip;
      }
      return true;
    }
  }
  return false;
}

XrResult XRAPI_CALL EnumerateReferenceSpaces(XrSession session, uint32_t capacity, uint32_t* count,
                                             XrReferenceSpaceType* out) {
  std::lock_guard lock(state().mutex);
  if (!valid_session(state(), session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (count == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const XrReferenceSpaceType values[] = {
      XR_REFERENCE_SPACE_TYPE_VIEW, XR_REFERENCE_SPACE_TYPE_LOCAL, XR_REFERENCE_SPACE_TYPE_STAGE};
  *count = 3;
  if (capacity == 0) {
    return XR_SUCCESS;
  }
  if (capacity < 3 || out == nullptr) {
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  for (int i = 0; i < 3; ++i) {
    out[i] = values[i];
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL CreateReferenceSpace(XrSession session, const XrReferenceSpaceCreateInfo* info,
                                         XrSpace* space) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || space == nullptr || info->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_VIEW &&
      info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_LOCAL &&
      info->referenceSpaceType != XR_REFERENCE_SPACE_TYPE_STAGE) {
    return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
  }
  SpaceObject s;
  s.reference = info->referenceSpaceType;
  s.pose_in_space = info->poseInReferenceSpace;
  const std::uint64_t id = rt.new_handle();
  rt.spaces[id] = s;
  *space = to_handle<XrSpace>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL CreateActionSpace(XrSession session, const XrActionSpaceCreateInfo* info,
                                      XrSpace* space) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || space == nullptr || info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const auto it = rt.actions.find(from_handle(info->action));
  if (it == rt.actions.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (it->second.type != XR_ACTION_TYPE_POSE_INPUT) {
    return XR_ERROR_ACTION_TYPE_MISMATCH;
  }
  SpaceObject s;
  s.is_action = true;
  s.action = from_handle(info->action);
  s.subaction = info->subactionPath;
  s.pose_in_space = info->poseInActionSpace;
  const std::uint64_t id = rt.new_handle();
  rt.spaces[id] = s;
  *space = to_handle<XrSpace>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroySpace(XrSpace space) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  return rt.spaces.erase(from_handle(space)) == 1 ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}

XrResult XRAPI_CALL GetReferenceSpaceBoundsRect(XrSession session, XrReferenceSpaceType type,
                                                XrExtent2Df* bounds) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (bounds == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (type != XR_REFERENCE_SPACE_TYPE_VIEW && type != XR_REFERENCE_SPACE_TYPE_LOCAL &&
      type != XR_REFERENCE_SPACE_TYPE_STAGE) {
    return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
  }
  if (type != XR_REFERENCE_SPACE_TYPE_STAGE) {
    *bounds = {0.0f, 0.0f};
    return XR_SPACE_BOUNDS_UNAVAILABLE;  // only the stage has bounds
  }
  *bounds = {kStageExtent, kStageExtent};
  return XR_SUCCESS;
}

XrResult XRAPI_CALL LocateSpace(XrSpace space, XrSpace base, XrTime time,
                                XrSpaceLocation* location) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto a = rt.spaces.find(from_handle(space));
  const auto b = rt.spaces.find(from_handle(base));
  if (a == rt.spaces.end() || b == rt.spaces.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (location == nullptr || location->type != XR_TYPE_SPACE_LOCATION) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (time <= 0) {
    return XR_ERROR_TIME_INVALID;
  }
  ScriptPose T_stage_a, T_stage_b;
  location->locationFlags = 0;
  location->pose = {{0, 0, 0, 1}, {0, 0, 0}};
  if (locate_in_stage(rt, a->second, time, T_stage_a) &&
      locate_in_stage(rt, b->second, time, T_stage_b)) {
    location->pose = to_xr(compose(inverse(T_stage_b), T_stage_a));
    location->locationFlags =
        XR_SPACE_LOCATION_POSITION_VALID_BIT | XR_SPACE_LOCATION_ORIENTATION_VALID_BIT |
        XR_SPACE_LOCATION_POSITION_TRACKED_BIT | XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL LocateViews(XrSession session, const XrViewLocateInfo* info,
                                XrViewState* view_state, uint32_t capacity, uint32_t* count,
                                XrView* views) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || view_state == nullptr || count == nullptr ||
      info->type != XR_TYPE_VIEW_LOCATE_INFO || view_state->type != XR_TYPE_VIEW_STATE) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  }
  if (info->displayTime <= 0) {
    return XR_ERROR_TIME_INVALID;
  }
  const auto base = rt.spaces.find(from_handle(info->space));
  if (base == rt.spaces.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  *count = 2;
  if (capacity == 0) {
    return XR_SUCCESS;
  }
  if (capacity < 2 || views == nullptr) {
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  ScriptPose T_stage_base;
  view_state->viewStateFlags = 0;
  if (!locate_in_stage(rt, base->second, info->displayTime, T_stage_base)) {
    return XR_SUCCESS;
  }
  const ScriptPose head = rt.sample(info->displayTime).head;
  for (uint32_t v = 0; v < 2; ++v) {
    const float side = v == 0 ? -0.5f : 0.5f;
    ScriptPose eye{Eigen::Vector3f(side * rt.script.ipd, 0, 0), Eigen::Quaternionf::Identity()};
    views[v].pose = to_xr(compose(inverse(T_stage_base), compose(head, eye)));
    views[v].fov = kFov;
  }
  view_state->viewStateFlags =
      XR_VIEW_STATE_POSITION_VALID_BIT | XR_VIEW_STATE_ORIENTATION_VALID_BIT |
      XR_VIEW_STATE_POSITION_TRACKED_BIT | XR_VIEW_STATE_ORIENTATION_TRACKED_BIT;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
