// The frame loop: xrWaitFrame, xrBeginFrame, xrEndFrame, in that order, one frame at a time.
// Display times are predicted on a virtual clock (one display period per frame) and each ended
// frame is recorded. By default nothing sleeps, so tests run as fast as the application renders;
// a script with "realtime": true paces xrWaitFrame to the wall clock like a headset's compositor
// (for sessions that talk to other processes running in real time).
//
// Stricter than the spec where the spec lets a runtime block: a second xrWaitFrame before the
// previous one's xrBeginFrame is refused with XR_ERROR_CALL_ORDER_INVALID (a single-threaded
// runtime would otherwise wait forever), and xrEndFrame must carry the display time predicted for
// the frame it ends (XR_ERROR_TIME_INVALID otherwise).

#include <chrono>
#include <mutex>
#include <thread>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

XrResult check(const Runtime& rt, XrSession session) {
  if (!rt.instance_live || rt.session == 0 || from_handle(session) != rt.session) {
    return XR_ERROR_HANDLE_INVALID;
  }
  return rt.session_state.running ? XR_SUCCESS : XR_ERROR_SESSION_NOT_RUNNING;
}

}  // namespace

XrResult XRAPI_CALL WaitFrame(XrSession session, const XrFrameWaitInfo* info, XrFrameState* frame) {
  Runtime& rt = state();
  std::unique_lock lock(rt.mutex);
  if (const XrResult r = check(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrWaitFrame", r);
  }
  if (frame == nullptr || frame->type != XR_TYPE_FRAME_STATE ||
      (info != nullptr && info->type != XR_TYPE_FRAME_WAIT_INFO)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SessionObject& s = rt.session_state;
  if (s.waited > s.begun) {
    return rt.refuse("xrWaitFrame", XR_ERROR_CALL_ORDER_INVALID);
  }
  ++s.waited;
  frame->predictedDisplayTime = rt.epoch + static_cast<XrTime>(s.waited) * rt.period();
  frame->predictedDisplayPeriod = rt.period();
  frame->shouldRender = (s.state == XR_SESSION_STATE_VISIBLE || s.state == XR_SESSION_STATE_FOCUSED)
                            ? XR_TRUE
                            : XR_FALSE;
  if (rt.script.realtime) {
    // Frame n is due n periods after the first xrWaitFrame, on the wall clock.
    using Clock = std::chrono::steady_clock;
    if (s.waited == 1) {
      s.wall_start = Clock::now();
    }
    const auto due =
        s.wall_start + std::chrono::nanoseconds(static_cast<XrTime>(s.waited - 1) * rt.period());
    lock.unlock();
    std::this_thread::sleep_until(due);
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL BeginFrame(XrSession session, const XrFrameBeginInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrBeginFrame", r);
  }
  if (info != nullptr && info->type != XR_TYPE_FRAME_BEGIN_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SessionObject& s = rt.session_state;
  if (s.begun == s.waited) {
    return rt.refuse("xrBeginFrame", XR_ERROR_CALL_ORDER_INVALID);  // no xrWaitFrame for it
  }
  const bool discarded = s.frame_open;
  ++s.begun;
  s.frame_open = true;
  s.begun_display_time = rt.epoch + static_cast<XrTime>(s.begun) * rt.period();
  return discarded ? XR_FRAME_DISCARDED : XR_SUCCESS;
}

XrResult XRAPI_CALL EndFrame(XrSession session, const XrFrameEndInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check(rt, session); r != XR_SUCCESS) {
    return r == XR_ERROR_HANDLE_INVALID ? r : rt.refuse("xrEndFrame", r);
  }
  if (info == nullptr || info->type != XR_TYPE_FRAME_END_INFO ||
      (info->layerCount > 0 && info->layers == nullptr)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SessionObject& s = rt.session_state;
  if (!s.frame_open) {
    return rt.refuse("xrEndFrame", XR_ERROR_CALL_ORDER_INVALID);
  }
  if (info->displayTime != s.begun_display_time) {
    return rt.refuse("xrEndFrame", XR_ERROR_TIME_INVALID);
  }
  if (info->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE) {
    return rt.refuse("xrEndFrame", XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
  }
  RecordedFrame f;
  f.index = s.begun - 1;
  f.predicted_display_time = s.begun_display_time;
  f.submitted_display_time = info->displayTime;
  f.layers = info->layerCount;
  f.synced_actions = rt.record.syncs_since_frame;
  for (uint32_t i = 0; i < info->layerCount; ++i) {
    const XrCompositionLayerBaseHeader* layer = info->layers[i];
    if (layer == nullptr) {
      return rt.refuse("xrEndFrame", XR_ERROR_LAYER_INVALID);
    }
    if (layer->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
      return rt.refuse("xrEndFrame", XR_ERROR_LAYER_INVALID);
    }
    const auto* projection = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
    if (projection->viewCount != 2 || projection->views == nullptr ||
        rt.spaces.count(from_handle(projection->space)) == 0) {
      return rt.refuse("xrEndFrame", XR_ERROR_VALIDATION_FAILURE);
    }
    for (uint32_t v = 0; v < 2; ++v) {
      const auto it = rt.swapchains.find(from_handle(projection->views[v].subImage.swapchain));
      if (it == rt.swapchains.end() || !it->second.acquired.empty()) {
        // Unknown swapchain, or an image acquired and not released this frame.
        return rt.refuse("xrEndFrame", XR_ERROR_LAYER_INVALID);
      }
    }
    f.projection_views += projection->viewCount;
  }
  rt.record.frames.push_back(f);
  rt.record.syncs_since_frame = 0;
  s.frame_open = false;
  ++s.ended;
  const XrTime now = info->displayTime;
  const Script& script = rt.script;
  if (script.lose_after_frames > 0 &&
      s.ended == static_cast<std::uint64_t>(script.lose_after_frames)) {
    rt.change_state(XR_SESSION_STATE_LOSS_PENDING, now);
  } else if (script.frames > 0 && s.ended >= static_cast<std::uint64_t>(script.frames) &&
             !s.exit_requested) {
    s.exit_requested = true;  // the scripted user takes the headset off
    stop_session(rt, now);
  } else if (s.ended == 1 && s.state == XR_SESSION_STATE_READY) {
    rt.change_state(XR_SESSION_STATE_SYNCHRONIZED, now);
    rt.change_state(XR_SESSION_STATE_VISIBLE, now);
    rt.change_state(XR_SESSION_STATE_FOCUSED, now);
  }
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
