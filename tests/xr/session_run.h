#pragma once
// One whole OpenXR session through whatever runtime XR_RUNTIME_JSON names: instance, session
// (bound to the EGL context current on this thread, or headless), swapchains, input and the
// frame loop, run until the runtime ends it, with `sink` as the application. What the tests ask
// of the pieces afterwards comes back with the loop's result.

#include "xr/frame_loop.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

namespace deixis::xr {

struct SessionRun {
  FrameLoopResult loop;
  bool hand_tracking = false;
  bool eye_gaze = false;
  std::uint64_t gaze_from_head_frames = 0;  // gaze estimated as the head's forward
  std::int64_t swapchain_format = 0;        // 0 for a headless session
};

inline SessionRun run_session_with(bool headless, FrameSink& sink) {
  InstanceOptions options;
  options.headless = headless;
  Instance instance(options);
  GlSession session(instance);
  Swapchains swapchains(instance, session);
  Input input(instance, session);
  FrameLoop loop(instance, session, swapchains, input);
  SessionRun run;
  run.loop = loop.run({}, sink);
  run.hand_tracking = input.hand_tracking();
  run.eye_gaze = input.eye_gaze();
  run.gaze_from_head_frames = input.gaze_from_head_frames();
  run.swapchain_format = swapchains.format();
  return run;
}

}  // namespace deixis::xr
