// xrApplyHapticFeedback and xrStopHapticFeedback (spec §11.7): checked as the spec says and
// recorded with the outputs they reach, so a test can see what the "controller" was told.

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

// The checks both calls start with; `out` is the vibration action.
XrResult find_output(Runtime& rt, XrSession session, const XrHapticActionInfo* info,
                     const ActionObject*& out) {
  if (!rt.instance_live || rt.session == 0 || from_handle(session) != rt.session) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_HAPTIC_ACTION_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const auto it = rt.actions.find(from_handle(info->action));
  if (it == rt.actions.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  const ActionObject& a = it->second;
  if (!rt.action_sets.at(a.set).attached) {
    return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  }
  if (a.type != XR_ACTION_TYPE_VIBRATION_OUTPUT) {
    return XR_ERROR_ACTION_TYPE_MISMATCH;
  }
  if (info->subactionPath != XR_NULL_PATH && std::find(a.subactions.begin(), a.subactions.end(),
                                                       info->subactionPath) == a.subactions.end()) {
    return XR_ERROR_PATH_UNSUPPORTED;
  }
  out = &a;
  return XR_SUCCESS;
}

// The record lists misuse of a valid action; bad handles and structures are the layer's to report.
XrResult refused(Runtime& rt, const char* call, XrResult r) {
  return r == XR_ERROR_HANDLE_INVALID || r == XR_ERROR_VALIDATION_FAILURE ? r : rt.refuse(call, r);
}

void record(Runtime& rt, const ActionObject& a, XrPath subaction, RecordedHaptic h) {
  if (rt.record.haptics.size() >= Record::kMaxHaptics) {
    ++rt.record.haptics_dropped;
    return;
  }
  h.time = rt.input_time();
  h.action = a.name;
  h.subaction = rt.path_string(subaction);
  for (const ActionBinding& b : a.bindings) {
    if (subaction == XR_NULL_PATH || subaction == b.user) {
      h.outputs.push_back(b.path);
    }
  }
  rt.record.haptics.push_back(std::move(h));
}

}  // namespace

XrResult XRAPI_CALL ApplyHapticFeedback(XrSession session, const XrHapticActionInfo* info,
                                        const XrHapticBaseHeader* haptic) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionObject* a = nullptr;
  if (const XrResult r = find_output(rt, session, info, a); r != XR_SUCCESS) {
    return refused(rt, "xrApplyHapticFeedback", r);
  }
  if (haptic == nullptr || haptic->type != XR_TYPE_HAPTIC_VIBRATION) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (rt.session_state.state != XR_SESSION_STATE_FOCUSED) {
    return XR_SESSION_NOT_FOCUSED;  // the application has no input focus: nothing vibrates
  }
  const auto* v = reinterpret_cast<const XrHapticVibration*>(haptic);
  RecordedHaptic h;
  h.duration = v->duration;
  h.frequency = v->frequency;
  h.amplitude = v->amplitude;
  record(rt, *a, info->subactionPath, std::move(h));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL StopHapticFeedback(XrSession session, const XrHapticActionInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const ActionObject* a = nullptr;
  if (const XrResult r = find_output(rt, session, info, a); r != XR_SUCCESS) {
    return refused(rt, "xrStopHapticFeedback", r);
  }
  if (rt.session_state.state != XR_SESSION_STATE_FOCUSED) {
    return XR_SESSION_NOT_FOCUSED;
  }
  RecordedHaptic h;
  h.stop = true;
  record(rt, *a, info->subactionPath, std::move(h));
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
