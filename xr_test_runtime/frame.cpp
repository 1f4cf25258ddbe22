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

#include <algorithm>
#include <chrono>
#include <mutex>
#include <thread>

#include "xr_test_runtime/api.h"
#include "xr_test_runtime/frame_capture.h"

namespace deixis::xrt {

namespace {

constexpr uint32_t kMaxLayers = 16;  // XrSystemGraphicsProperties::maxLayerCount

const char* blend_mode_name(XrEnvironmentBlendMode mode) {
  switch (mode) {
    case XR_ENVIRONMENT_BLEND_MODE_OPAQUE:
      return "OPAQUE";
    case XR_ENVIRONMENT_BLEND_MODE_ADDITIVE:
      return "ADDITIVE";
    case XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND:
      return "ALPHA_BLEND";
    default:
      return "?";
  }
}

// The layer flags by name, for the record; false when a bit is not one of the core spec's.
bool flag_names(XrCompositionLayerFlags flags, std::vector<std::string>& out) {
  const std::pair<XrCompositionLayerFlags, const char*> names[] = {
      {XR_COMPOSITION_LAYER_CORRECT_CHROMATIC_ABERRATION_BIT, "CORRECT_CHROMATIC_ABERRATION"},
      {XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT, "BLEND_TEXTURE_SOURCE_ALPHA"},
      {XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT, "UNPREMULTIPLIED_ALPHA"}};
  XrCompositionLayerFlags known = 0;
  for (const auto& [bit, name] : names) {
    known |= bit;
    if ((flags & bit) != 0) {
      out.emplace_back(name);
    }
  }
  return (flags & ~known) == 0;
}

// A swapchain sub-image a layer shows: a known swapchain with every image released, and a
// rectangle inside it.
XrResult check_sub_image(const Runtime& rt, const XrSwapchainSubImage& sub) {
  const auto it = rt.swapchains.find(from_handle(sub.swapchain));
  if (it == rt.swapchains.end() || !it->second.acquired.empty()) {
    return XR_ERROR_LAYER_INVALID;  // unknown, or an image acquired and not released
  }
  const XrRect2Di& r = sub.imageRect;
  if (r.offset.x < 0 || r.offset.y < 0 || r.extent.width <= 0 || r.extent.height <= 0 ||
      static_cast<std::uint64_t>(r.offset.x) + static_cast<std::uint64_t>(r.extent.width) >
          it->second.width ||
      static_cast<std::uint64_t>(r.offset.y) + static_cast<std::uint64_t>(r.extent.height) >
          it->second.height) {
    return XR_ERROR_SWAPCHAIN_RECT_INVALID;
  }
  return sub.imageArrayIndex == 0 ? XR_SUCCESS : XR_ERROR_VALIDATION_FAILURE;
}

// A projection layer (one view per eye) or a quad layer, checked as the spec says; `out` is
// what the record keeps of it.
XrResult check_layer(const Runtime& rt, const XrCompositionLayerBaseHeader* layer,
                     RecordedLayer& out) {
  if (layer == nullptr) {
    return XR_ERROR_LAYER_INVALID;
  }
  if (rt.spaces.count(from_handle(layer->space)) == 0 ||
      !flag_names(layer->layerFlags, out.flags)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (layer->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
    const auto* projection = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
    if (projection->viewCount != 2 || projection->views == nullptr) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    for (uint32_t v = 0; v < 2; ++v) {
      if (projection->views[v].type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW) {
        return XR_ERROR_VALIDATION_FAILURE;
      }
      if (const XrResult r = check_sub_image(rt, projection->views[v].subImage); r != XR_SUCCESS) {
        return r;
      }
    }
    out.type = "projection";
    out.views = 2;
    return XR_SUCCESS;
  }
  if (layer->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
    const auto* quad = reinterpret_cast<const XrCompositionLayerQuad*>(layer);
    if (!(quad->size.width > 0.0f) || !(quad->size.height > 0.0f) ||
        (quad->eyeVisibility != XR_EYE_VISIBILITY_BOTH &&
         quad->eyeVisibility != XR_EYE_VISIBILITY_LEFT &&
         quad->eyeVisibility != XR_EYE_VISIBILITY_RIGHT)) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    if (const XrResult r = check_sub_image(rt, quad->subImage); r != XR_SUCCESS) {
      return r;
    }
    out.type = "quad";
    out.views = 1;
    return XR_SUCCESS;
  }
  return XR_ERROR_LAYER_INVALID;  // cube, cylinder, equirect: extensions the runtime lacks
}

// The layer's images as the record keeps them for a captured frame.
void capture_layer(const Runtime& rt, const XrCompositionLayerBaseHeader& layer,
                   std::uint64_t frame, uint32_t index, RecordedLayer& out) {
  const BoundContext bound(rt.session_state.graphics);
  if (!bound.ok()) {
    return;
  }
  const auto add = [&](const XrSwapchainSubImage& sub, uint32_t view) {
    const SwapchainObject& swapchain = rt.swapchains.at(from_handle(sub.swapchain));
    const std::string file = rt.record_path + ".frame" + std::to_string(frame) + ".layer" +
                             std::to_string(index) + ".view" + std::to_string(view) + ".pam";
    out.images.push_back(capture_view(rt.session_state.graphics.gl, swapchain,
                                      swapchain.last_released, sub.imageRect, file));
  };
  if (layer.type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
    const auto& projection = reinterpret_cast<const XrCompositionLayerProjection&>(layer);
    for (uint32_t v = 0; v < projection.viewCount; ++v) {
      add(projection.views[v].subImage, v);
    }
  } else {
    add(reinterpret_cast<const XrCompositionLayerQuad&>(layer).subImage, 0);
  }
}

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
  const std::vector<XrEnvironmentBlendMode>& modes = rt.script.blend_modes;
  if (std::find(modes.begin(), modes.end(), info->environmentBlendMode) == modes.end()) {
    return rt.refuse("xrEndFrame", XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
  }
  if (info->layerCount > kMaxLayers) {
    return rt.refuse("xrEndFrame", XR_ERROR_LAYER_LIMIT_EXCEEDED);
  }
  RecordedFrame f;
  f.index = s.begun - 1;
  f.predicted_display_time = s.begun_display_time;
  f.submitted_display_time = info->displayTime;
  f.layers = info->layerCount;
  f.synced_actions = rt.record.syncs_since_frame;
  f.blend_mode = blend_mode_name(info->environmentBlendMode);
  const bool capture = std::find(rt.script.capture_frames.begin(), rt.script.capture_frames.end(),
                                 static_cast<long>(f.index)) != rt.script.capture_frames.end() &&
                       !rt.record_path.empty();
  for (uint32_t i = 0; i < info->layerCount; ++i) {
    RecordedLayer layer;
    if (const XrResult r = check_layer(rt, info->layers[i], layer); r != XR_SUCCESS) {
      return rt.refuse("xrEndFrame", r);
    }
    if (capture) {
      capture_layer(rt, *info->layers[i], f.index, i, layer);
    }
    if (layer.type == "projection") {
      f.projection_views += layer.views;
    }
    f.layer_list.push_back(std::move(layer));
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
