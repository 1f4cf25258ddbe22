// Session lifecycle: create (with an OpenGL binding or headless), begin, end, request exit,
// destroy. The runtime enforces the spec's order and drives the states (IDLE, READY, then after
// the first frame SYNCHRONIZED, VISIBLE, FOCUSED; STOPPING on exit; EXITING after xrEndSession).

#include <cstdio>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

bool valid_session(const Runtime& rt, XrSession session) {
  return rt.instance_live && rt.session != 0 && from_handle(session) == rt.session;
}

}  // namespace

// Walks the session down to STOPPING the way the spec orders states.
void stop_session(Runtime& rt, XrTime time) {
  const XrSessionState s = rt.session_state.state;
  if (s == XR_SESSION_STATE_FOCUSED) {
    rt.change_state(XR_SESSION_STATE_VISIBLE, time);
  }
  if (s == XR_SESSION_STATE_FOCUSED || s == XR_SESSION_STATE_VISIBLE) {
    rt.change_state(XR_SESSION_STATE_SYNCHRONIZED, time);
  }
  rt.change_state(XR_SESSION_STATE_STOPPING, time);
}

XrResult XRAPI_CALL CreateSession(XrInstance instance, const XrSessionCreateInfo* info,
                                  XrSession* session) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!rt.instance_live || from_handle(instance) != rt.instance) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || session == nullptr || info->type != XR_TYPE_SESSION_CREATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->systemId != 1) {
    return XR_ERROR_SYSTEM_INVALID;
  }
  if (rt.session != 0) {
    return rt.refuse("xrCreateSession", XR_ERROR_LIMIT_REACHED);
  }
  SessionGraphics graphics;
  std::string problem;
  if (!find_graphics_binding(info->next, rt.extension_enabled("XR_MNDX_egl_enable"), graphics,
                             problem)) {
    std::fprintf(stderr, "deixis xr test runtime: xrCreateSession: %s\n", problem.c_str());
    return rt.refuse("xrCreateSession", XR_ERROR_GRAPHICS_DEVICE_INVALID);
  }
  const bool gl = graphics.binding != GraphicsBinding::kNone;
  if (gl) {
    if (!rt.extension_enabled("XR_KHR_opengl_enable")) {
      return rt.refuse("xrCreateSession", XR_ERROR_VALIDATION_FAILURE);
    }
    if (!rt.graphics_requirements_queried) {
      return rt.refuse("xrCreateSession", XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING);
    }
  } else if (!rt.extension_enabled("XR_MND_headless")) {
    // Without XR_MND_headless a session needs a binding the runtime knows (an EGL one only with
    // XR_MNDX_egl_enable enabled).
    return rt.refuse("xrCreateSession", XR_ERROR_GRAPHICS_DEVICE_INVALID);
  }
  rt.session = rt.new_handle();
  rt.session_state = {};
  rt.session_state.headless = !gl;
  rt.session_state.graphics = graphics;
  rt.record.graphics = graphics.binding == GraphicsBinding::kXlib  ? "xlib"
                       : graphics.binding == GraphicsBinding::kEgl ? "egl"
                                                                   : "headless";
  *session = to_handle<XrSession>(rt.session);
  rt.change_state(XR_SESSION_STATE_IDLE, rt.epoch);
  rt.change_state(XR_SESSION_STATE_READY, rt.epoch);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroySession(XrSession session) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  rt.spaces.clear();  // children of the session
  if (const BoundContext bound(rt.session_state.graphics); bound.ok()) {
    for (const auto& [id, swapchain] : rt.swapchains) {  // those the application left
      rt.session_state.graphics.gl.DeleteTextures(static_cast<GLsizei>(swapchain.textures.size()),
                                                  swapchain.textures.data());
    }
  }
  rt.swapchains.clear();
  rt.hand_trackers.clear();
  rt.session = 0;
  rt.session_state = {};
  return XR_SUCCESS;
}

XrResult XRAPI_CALL BeginSession(XrSession session, const XrSessionBeginInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_SESSION_BEGIN_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SessionObject& s = rt.session_state;
  if (s.running) {
    return rt.refuse("xrBeginSession", XR_ERROR_SESSION_RUNNING);
  }
  if (s.state != XR_SESSION_STATE_READY) {
    return rt.refuse("xrBeginSession", XR_ERROR_SESSION_NOT_READY);
  }
  if (info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO) {
    return rt.refuse("xrBeginSession", XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  }
  s.running = true;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL EndSession(XrSession session) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  SessionObject& s = rt.session_state;
  if (!s.running) {
    return rt.refuse("xrEndSession", XR_ERROR_SESSION_NOT_RUNNING);
  }
  if (s.state != XR_SESSION_STATE_STOPPING) {
    return rt.refuse("xrEndSession", XR_ERROR_SESSION_NOT_STOPPING);
  }
  s.running = false;
  s.frame_open = false;
  const XrTime now = rt.epoch + static_cast<XrTime>(s.waited + 1) * rt.period();
  rt.change_state(XR_SESSION_STATE_IDLE, now);
  if (s.exit_requested) {
    rt.change_state(XR_SESSION_STATE_EXITING, now);
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL RequestExitSession(XrSession session) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  SessionObject& s = rt.session_state;
  if (!s.running) {
    return rt.refuse("xrRequestExitSession", XR_ERROR_SESSION_NOT_RUNNING);
  }
  if (!s.exit_requested && s.state != XR_SESSION_STATE_STOPPING) {
    s.exit_requested = true;
    stop_session(rt, rt.epoch + static_cast<XrTime>(s.waited + 1) * rt.period());
  }
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
