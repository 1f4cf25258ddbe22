#include "xr/frame_loop.h"

#include <chrono>
#include <thread>

#include "core/error.h"
#include "xr/xr_struct.h"

namespace deixis::xr {

namespace {

constexpr XrViewConfigurationType kViewConfig = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;

}  // namespace

FrameLoop::FrameLoop(const Instance& instance, const GlSession& session, Swapchains& swapchains,
                     Input& input)
    : instance_(&instance), session_(&session), swapchains_(&swapchains), input_(&input) {
  const std::uint32_t n = instance.view_config().count;
  views_.assign(n, make<XrView>(XR_TYPE_VIEW));
  projection_views_.assign(
      n, make<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW));
}

void FrameLoop::apply(const SessionEvent& event) {
  const XrInstance xi = instance_->handle();
  const XrSession s = session_->handle();
  const SessionStep step = on_event(machine_, event);
  if (step.actions.begin_session) {
    auto bi = make<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
    bi.primaryViewConfigurationType = kViewConfig;
    XR_CHECK(xi, xrBeginSession(s, &bi));
  }
  if (step.actions.end_session) {
    XR_CHECK(xi, xrEndSession(s));
  }
  if (step.actions.request_exit_session) {
    XR_CHECK(xi, xrRequestExitSession(s));
  }
  machine_ = step.next;
}

bool FrameLoop::poll_events() {
  const XrInstance xi = instance_->handle();
  bool any = false;
  auto event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
  for (XrResult r = xrPollEvent(xi, &event); r == XR_SUCCESS; r = xrPollEvent(xi, &event)) {
    any = true;
    if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
      const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
      apply({SessionEventKind::kStateChanged, static_cast<SessionState>(changed.state)});
    } else if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) {
      apply({SessionEventKind::kInstanceLossPending, SessionState::kUnknown});
    }
    event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
  }
  return any;
}

FrameLoopResult FrameLoop::run(const FrameLoopOptions& options, FrameSink& sink) {
  using Clock = std::chrono::steady_clock;
  FrameLoopResult result;
  auto idle_since = Clock::now();
  while (!machine_.finished) {
    const bool events = poll_events();
    const bool time_is_up = options.seconds > 0.0 && seconds_ >= options.seconds;
    if ((time_is_up || sink.wants_exit()) && !machine_.exit_requested && !machine_.finished) {
      apply({SessionEventKind::kExitRequested, SessionState::kUnknown});
    }
    if (machine_.finished) {
      break;
    }
    if (!runs_frame_loop(machine_)) {
      if (!events) {
        if (std::chrono::duration<double>(Clock::now() - idle_since).count() >
            options.wall_timeout) {
          throw Error("the OpenXR session stayed " + std::string(to_string(machine_.state)) +
                      " for " + std::to_string(options.wall_timeout) + " s");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a real runtime's IDLE
      }
      continue;
    }
    idle_since = Clock::now();
    frame(sink, result);
  }
  result.lost = machine_.lost;
  return result;
}

void FrameLoop::frame(FrameSink& sink, FrameLoopResult& result) {
  const XrInstance xi = instance_->handle();
  const XrSession s = session_->handle();
  auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
  auto wi = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  XR_CHECK(xi, xrWaitFrame(s, &wi, &fs));
  auto bi = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  XR_CHECK(xi, xrBeginFrame(s, &bi));
  if (frame_index_ == 0) {
    first_display_time_ = fs.predictedDisplayTime;
  }
  seconds_ = static_cast<double>(fs.predictedDisplayTime - first_display_time_) * 1e-9;
  Buttons buttons;
  if (syncs_actions(machine_)) {
    input_->sync();
    buttons = input_->buttons();
  }
  const TrackingFrame user = input_->locate(fs.predictedDisplayTime, seconds_);
  const FrameInfo info{frame_index_, fs.predictedDisplayTime,    fs.predictedDisplayPeriod,
                       seconds_,     fs.shouldRender == XR_TRUE, machine_.state,
                       buttons};
  sink.on_frame(info, user);

  auto layer = make<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
  layer.layerFlags = projection_layer_flags(instance_->view_config().blend_mode);
  const XrCompositionLayerBaseHeader* layers[] = {
      reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
  std::uint32_t layer_count = 0;
  if (fs.shouldRender == XR_TRUE && swapchains_->count() > 0) {
    auto li = make<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
    li.viewConfigurationType = kViewConfig;
    li.displayTime = fs.predictedDisplayTime;
    li.space = session_->stage();
    auto vs = make<XrViewState>(XR_TYPE_VIEW_STATE);
    std::uint32_t n = 0;
    XR_CHECK(xi, xrLocateViews(s, &li, &vs, static_cast<std::uint32_t>(views_.size()), &n,
                               views_.data()));
    const bool located = pose_valid(vs.viewStateFlags) && n == swapchains_->count();
    for (std::uint32_t i = 0; located && i < n; ++i) {
      const std::optional<Pose> eye = to_pose(views_[i].pose);
      const render::RenderTarget target = swapchains_->acquire(i);
      if (eye) {
        render::Camera camera;
        camera.T_world_eye = *eye;
        camera.fov = {views_[i].fov.angleLeft, views_[i].fov.angleRight, views_[i].fov.angleUp,
                      views_[i].fov.angleDown};
        sink.render_view(i, camera, target);
      }
      swapchains_->release(i);
      auto& pv = projection_views_[i];
      pv.pose = views_[i].pose;
      pv.fov = views_[i].fov;
      pv.subImage = swapchains_->sub_image(i);
    }
    if (located) {
      layer.space = session_->stage();
      layer.viewCount = n;
      layer.views = projection_views_.data();
      layer_count = 1;
      result.rendered_views += n;
    }
  }
  auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  ei.displayTime = fs.predictedDisplayTime;
  ei.environmentBlendMode = instance_->view_config().blend_mode;
  ei.layerCount = layer_count;
  ei.layers = layers;
  XR_CHECK(xi, xrEndFrame(s, &ei));
  ++frame_index_;
  ++result.frames;
  if (machine_.state == SessionState::kFocused) {
    ++result.focused_frames;
  }
}

}  // namespace deixis::xr
