#pragma once
// The OpenXR event and frame loop by the rules of Khronos' hello_xr: events drive the
// session lifecycle through xr/session_state.h; while the session runs, every frame is
// xrWaitFrame → xrBeginFrame → (xrSyncActions with focus) → input at the predicted display time →
// xrLocateViews → render each view into its swapchain image when shouldRender → xrEndFrame with
// that same predicted display time. Views' poses and FOVs go to the renderer as given.

#include <openxr/openxr.h>

#include <cstdint>
#include <vector>

#include "core/tracking.h"
#include "render/camera.h"
#include "render/render_target.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/session_state.h"
#include "xr/swapchains.h"

namespace deixis::xr {

struct FrameInfo {
  std::uint64_t index = 0;  // 0, 1, ... frames of this loop
  XrTime predicted_display_time = 0;
  XrDuration period = 0;
  double seconds = 0.0;  // predicted display time since the first frame's
  bool should_render = false;
  SessionState state = SessionState::kUnknown;
  Buttons buttons;  // synced in this frame; all up without focus
};

// The application's side of a frame. Called on the loop's thread with the GL context current;
// neither call may allocate per frame.
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // After the user's input was located at the frame's predicted display time.
  virtual void on_frame(const FrameInfo& frame, const TrackingFrame& user) = 0;
  // Draw view `view` (0 left, 1 right) into `target` from `camera`.
  virtual void render_view(std::uint32_t view, const render::Camera& camera,
                           const render::RenderTarget& target) = 0;
  // True once the application wants to stop (e.g. its network session failed): the loop asks
  // the runtime to exit and ends the session through the lifecycle, as for `seconds`.
  virtual bool wants_exit() const { return false; }
};

struct FrameLoopOptions {
  double seconds = 0.0;  // ask to exit after this much display time; 0: until the runtime ends
  double wall_timeout = 60.0;  // s without the session running before giving up (wall clock)
};

struct FrameLoopResult {
  std::uint64_t frames = 0;          // ended
  std::uint64_t rendered_views = 0;  // projection views submitted
  std::uint64_t focused_frames = 0;  // ended while the session was FOCUSED (input reached us)
  bool lost = false;                 // the session or instance was lost
};

class FrameLoop {
 public:
  // `swapchains` is empty for a headless session (frames are submitted without layers).
  FrameLoop(const Instance& instance, const GlSession& session, Swapchains& swapchains,
            Input& input);

  // Runs until the session exits (the runtime ends it, or `options.seconds` passed and the exit
  // went through the lifecycle). Throws deixis::Error naming the failing call and its XrResult.
  FrameLoopResult run(const FrameLoopOptions& options, FrameSink& sink);

 private:
  void apply(const SessionEvent& event);
  bool poll_events();  // true when there was an event
  void frame(FrameSink& sink, FrameLoopResult& result);

  const Instance* instance_;
  const GlSession* session_;
  Swapchains* swapchains_;
  Input* input_;
  SessionMachine machine_;
  std::vector<XrView> views_;
  std::vector<XrCompositionLayerProjectionView> projection_views_;
  XrTime first_display_time_ = 0;
  std::uint64_t frame_index_ = 0;
  double seconds_ = 0.0;
};

}  // namespace deixis::xr
