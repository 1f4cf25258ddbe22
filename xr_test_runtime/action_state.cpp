// xrSyncActions and the action states it produces (spec §11.5): boolean, float, vector2 and pose
// states per subaction path, read from the script's controls at the last frame's predicted
// display time; changedSinceLastSync and lastChangeTime against the previous sync; isActive when
// the action's set is active in the sync, an input is bound and the session is FOCUSED.
// Several bound inputs combine as the spec says: booleans OR, floats the largest magnitude,
// vector2s the longest.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

bool valid_session(const Runtime& rt, XrSession session) {
  return rt.instance_live && rt.session != 0 && from_handle(session) == rt.session;
}

// What one bound input reads now: (x, y); booleans and floats use x.
Eigen::Vector2f read(const Runtime& rt, const ActionObject& action, const ActionBinding& b,
                     double t) {
  if (b.component == kPose) {
    return {1.0f, 0.0f};
  }
  const ScriptControl c = rt.script.control_at(t, b.top, b.identifier->identifier);
  float v = 0.0f;
  switch (b.component) {
    case kClick:
      v = c.click ? 1.0f : 0.0f;
      break;
    case kTouch:
      v = c.touch ? 1.0f : 0.0f;
      break;
    case kValue:
      v = c.value;
      break;
    case kForce:
      v = c.force;
      break;
    case kX:
      v = c.x;
      break;
    case kY:
      v = c.y;
      break;
    case kX | kY:
      return {c.x, c.y};
    default:
      break;
  }
  if (action.type == XR_ACTION_TYPE_BOOLEAN_INPUT) {
    v = v >= 0.5f ? 1.0f : 0.0f;  // an analog input read as a button (§11.5.1: a threshold)
  }
  return {v, 0.0f};
}

// Whether the sync activates `action` for inputs on `user`: its set is listed with no subaction
// path or with `user`.
bool set_active(const XrActionsSyncInfo& info, const ActionObject& action, XrPath user) {
  for (uint32_t i = 0; i < info.countActiveActionSets; ++i) {
    const XrActiveActionSet& a = info.activeActionSets[i];
    if (from_handle(a.actionSet) == action.set &&
        (a.subactionPath == XR_NULL_PATH || a.subactionPath == user)) {
      return true;
    }
  }
  return false;
}

// One action's new state for `state.subaction`.
void update(const Runtime& rt, const XrActionsSyncInfo& info, const ActionObject& action,
            bool focused, XrTime now, ActionState& state) {
  const double t = static_cast<double>(now - rt.epoch - rt.period()) * 1e-9;
  bool active = false;
  Eigen::Vector2f value = Eigen::Vector2f::Zero();
  for (const ActionBinding& b : action.bindings) {
    if (!focused || (state.subaction != XR_NULL_PATH && state.subaction != b.user) ||
        !set_active(info, action, b.user)) {
      continue;
    }
    active = true;
    const Eigen::Vector2f v = read(rt, action, b, t);
    const bool larger = action.type == XR_ACTION_TYPE_VECTOR2F_INPUT
                            ? v.norm() > value.norm()
                            : std::abs(v.x()) > std::abs(value.x());
    if (larger) {
      value = v;
    }
  }
  const bool differs = value.x() != state.x || value.y() != state.y;
  state.changed = active && state.active && differs;
  state.active = active;
  state.x = value.x();
  state.y = value.y();
  if (state.changed) {
    state.last_change = now;
  } else if (!active) {
    state.last_change = 0;
  }
}

// The checks every xrGetActionState* starts with; `out` is the state for the subaction path.
XrResult find_state(const Runtime& rt, XrSession session, const XrActionStateGetInfo* info,
                    XrActionType type, const ActionState*& out) {
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_ACTION_STATE_GET_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const auto it = rt.actions.find(from_handle(info->action));
  if (it == rt.actions.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  const ActionObject& a = it->second;
  if (!rt.action_sets.at(a.set).attached || a.states.empty()) {
    return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  }
  if (a.type != type) {
    return XR_ERROR_ACTION_TYPE_MISMATCH;
  }
  for (const ActionState& s : a.states) {
    if (s.subaction == info->subactionPath) {
      out = &s;
      return XR_SUCCESS;
    }
  }
  return XR_ERROR_PATH_UNSUPPORTED;  // not one of the action's subaction paths
}

// What boolean, float and vector2 states share.
template <typename Out>
void fill_change(const ActionState& s, Out& out) {
  out.changedSinceLastSync = s.changed ? XR_TRUE : XR_FALSE;
  out.lastChangeTime = s.last_change;
  out.isActive = s.active ? XR_TRUE : XR_FALSE;
}

void announce_profiles(Runtime& rt) {
  SessionObject& s = rt.session_state;
  if (s.profiles_announced || !s.running) {
    return;  // the event is only for running sessions
  }
  s.profiles_announced = true;
  if (std::none_of(s.profiles.begin(), s.profiles.end(), [](const Profile* p) { return p; })) {
    return;
  }
  XrEventDataBuffer buffer{XR_TYPE_EVENT_DATA_BUFFER, nullptr, {}};
  const XrEventDataInteractionProfileChanged changed{XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED,
                                                     nullptr, to_handle<XrSession>(rt.session)};
  static_assert(sizeof(changed) <= sizeof(buffer));
  std::memcpy(&buffer, &changed, sizeof(changed));
  rt.events.push_back(buffer);
}

}  // namespace

XrResult XRAPI_CALL SyncActions(XrSession session, const XrActionsSyncInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_ACTIONS_SYNC_INFO ||
      (info->countActiveActionSets > 0 && info->activeActionSets == nullptr)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (!rt.session_state.actions_attached) {
    return rt.refuse("xrSyncActions", XR_ERROR_ACTIONSET_NOT_ATTACHED);
  }
  for (uint32_t i = 0; i < info->countActiveActionSets; ++i) {
    const XrActiveActionSet& a = info->activeActionSets[i];
    const auto set = rt.action_sets.find(from_handle(a.actionSet));
    if (set == rt.action_sets.end()) {
      return XR_ERROR_HANDLE_INVALID;
    }
    if (!set->second.attached) {
      return rt.refuse("xrSyncActions", XR_ERROR_ACTIONSET_NOT_ATTACHED);
    }
    bool top_level = a.subactionPath == XR_NULL_PATH;
    for (std::size_t t = 0; t < kTopLevelCount; ++t) {
      top_level =
          top_level || rt.path_string(a.subactionPath) == top_level_path(static_cast<TopLevel>(t));
    }
    if (!top_level) {
      return rt.refuse("xrSyncActions", XR_ERROR_PATH_UNSUPPORTED);
    }
  }
  ++rt.record.syncs_since_frame;
  announce_profiles(rt);
  const bool focused = rt.session_state.state == XR_SESSION_STATE_FOCUSED;
  const XrTime now = rt.input_time();
  for (auto& [id, action] : rt.actions) {
    for (ActionState& s : action.states) {
      update(rt, *info, action, focused, now, s);
    }
  }
  return focused ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED;
}

XrResult XRAPI_CALL GetActionStateBoolean(XrSession session, const XrActionStateGetInfo* info,
                                          XrActionStateBoolean* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionState* s = nullptr;
  if (const XrResult r = find_state(rt, session, info, XR_ACTION_TYPE_BOOLEAN_INPUT, s);
      r != XR_SUCCESS) {
    return r;
  }
  if (out == nullptr || out->type != XR_TYPE_ACTION_STATE_BOOLEAN) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  out->currentState = s->x != 0.0f ? XR_TRUE : XR_FALSE;
  fill_change(*s, *out);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetActionStateFloat(XrSession session, const XrActionStateGetInfo* info,
                                        XrActionStateFloat* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionState* s = nullptr;
  if (const XrResult r = find_state(rt, session, info, XR_ACTION_TYPE_FLOAT_INPUT, s);
      r != XR_SUCCESS) {
    return r;
  }
  if (out == nullptr || out->type != XR_TYPE_ACTION_STATE_FLOAT) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  out->currentState = s->x;
  fill_change(*s, *out);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetActionStateVector2f(XrSession session, const XrActionStateGetInfo* info,
                                           XrActionStateVector2f* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionState* s = nullptr;
  if (const XrResult r = find_state(rt, session, info, XR_ACTION_TYPE_VECTOR2F_INPUT, s);
      r != XR_SUCCESS) {
    return r;
  }
  if (out == nullptr || out->type != XR_TYPE_ACTION_STATE_VECTOR2F) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  out->currentState = {s->x, s->y};
  fill_change(*s, *out);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetActionStatePose(XrSession session, const XrActionStateGetInfo* info,
                                       XrActionStatePose* out) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionState* s = nullptr;
  if (const XrResult r = find_state(rt, session, info, XR_ACTION_TYPE_POSE_INPUT, s);
      r != XR_SUCCESS) {
    return r;
  }
  if (out == nullptr || out->type != XR_TYPE_ACTION_STATE_POSE) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  out->isActive = s->active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
