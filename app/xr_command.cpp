// `deixis xr`: the headset user's side through OpenXR (docs/xr.md). This first version runs
// without networking: the remote person is the other site's scripted virtual user, performed
// locally in their room and translated into this room by presence::RemoteAvatar at 30 Hz of
// display time; each frame the headset user's tracking is read from the runtime and both eyes
// see this room, its objects and the remote person's avatar.

#include <cstdio>
#include <optional>
#include <string>

#include "app/commands.h"
#include "app/moe_weights.h"
#include "app/site_config.h"
#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "gesture/error.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "ik/avatar_solver.h"
#include "presence/remote_avatar.h"
#include "render/headless_context.h"
#include "render/renderer.h"
#include "xr/frame_loop.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

constexpr double kTick = 1.0 / 30.0;  // s: translation rate (DESIGN §3)

using Networks = MoeNetworks;

// The remote person: the other site's virtual user performed in their room.
capture::ScriptPerformance perform_remote(const SiteConfig& remote, const ik::AvatarSolver& solver,
                                          const fs::path& source, double seconds) {
  if (!remote.virtual_user) {
    throw Error(source.string() +
                ": virtual_user: missing (the remote person is this site's scripted user)");
  }
  const Pose partner = presence::avatar_origin(solver, remote.remote_avatar.T_world_floor());
  const capture::VirtualUserScene scene{remote.user.T_world_floor(), remote.target_map.objects,
                                        partner.translation};
  try {
    const VirtualUser& user = *remote.virtual_user;
    return capture::perform_script(capture::find_subject(user.subject), user.script, scene,
                                   user.seed, seconds);
  } catch (const Error& e) {
    throw Error(source.string() + ": " + e.what());
  }
}

// Joins the OpenXR frame loop to the translator and the renderer; allocates nothing per frame.
class XrSink final : public xr::FrameSink {
 public:
  XrSink(const SiteConfig& site, const capture::ScriptPerformance& remote,
         presence::RemoteAvatar& avatar, render::Renderer& renderer, render::SkinnedMeshId mesh)
      : site_(site), remote_(remote), avatar_(avatar), renderer_(renderer), mesh_(mesh) {}

  void on_frame(const xr::FrameInfo& frame, const TrackingFrame& user) override {
    if ((user.valid & tracked::kHead) != 0) {
      user_head_ = user.T_world_head.translation;
    }
    for (std::uint8_t bit = 1; bit <= tracked::kRightHand;
         bit = static_cast<std::uint8_t>(bit << 1)) {
      valid_counts_[bit == tracked::kHead       ? 0
                    : bit == tracked::kGaze     ? 1
                    : bit == tracked::kLeftHand ? 2
                                                : 3] += (user.valid & bit) != 0 ? 1 : 0;
    }
    ++frames_;
    const auto& frames = remote_.sequence.frames;
    const LocalTargets room{&site_.target_map, user_head_};
    while (static_cast<double>(ticks_) * kTick <= frame.seconds && !frames.empty()) {
      const std::size_t i = std::min<std::size_t>(ticks_, frames.size() - 1);
      TrackingFrame f = frames[i];
      f.time = static_cast<double>(ticks_) * kTick;
      visible_ticks_ += avatar_.tick(&f, room) ? 1 : 0;
      ++ticks_;
    }
  }

  void render_view(std::uint32_t, const render::Camera& camera,
                   const render::RenderTarget& target) override {
    render::SceneView view;
    view.camera = camera;
    if (avatar_.visible()) {
      avatars_[0] = {mesh_, avatar_.T_world_model(), avatar_.model_pose()};
      view.avatars = avatars_;
    }
    renderer_.render(view, target);
  }

  void print_summary(const xr::FrameLoopResult& r) const {
    std::printf(
        "frames %llu, views rendered %llu, translation ticks %llu (avatar visible in %llu)\n"
        "headset user tracked: head %llu, gaze %llu, left hand %llu, right hand %llu frames\n",
        static_cast<unsigned long long>(r.frames),
        static_cast<unsigned long long>(r.rendered_views), static_cast<unsigned long long>(ticks_),
        static_cast<unsigned long long>(visible_ticks_),
        static_cast<unsigned long long>(valid_counts_[0]),
        static_cast<unsigned long long>(valid_counts_[1]),
        static_cast<unsigned long long>(valid_counts_[2]),
        static_cast<unsigned long long>(valid_counts_[3]));
  }

 private:
  const SiteConfig& site_;
  const capture::ScriptPerformance& remote_;
  presence::RemoteAvatar& avatar_;
  render::Renderer& renderer_;
  render::SkinnedMeshId mesh_;
  std::array<render::AvatarDraw, 1> avatars_;
  Vec3 user_head_ = Vec3(0, 1.6f, 0);
  std::uint64_t frames_ = 0;
  std::uint64_t ticks_ = 0;
  std::uint64_t visible_ticks_ = 0;
  std::array<std::uint64_t, 4> valid_counts_{};
};

}  // namespace

int run_xr(const XrRunOptions& o) {
  std::optional<SiteConfig> site;
  std::optional<SiteConfig> remote_site;
  std::optional<avatar::Avatar> avatar;
  std::optional<ik::AvatarSolver> solver;
  std::optional<capture::ScriptPerformance> remote;
  std::optional<Networks> networks;
  try {
    site = read_site_config(o.site);
    remote_site = read_site_config(o.remote_site);
    avatar = avatar::load_avatar(site->avatar_path);
    solver = ik::AvatarSolver::build(avatar->rig);
    remote = perform_remote(*remote_site, *solver, o.remote_site, o.seconds);
    networks = load_moe_networks(o.weights_dir, remote->sequence.calibration.deictic_hand);
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis xr: %s\n", e.what());
    return 2;
  }
  try {
    presence::RemoteAvatar remote_avatar(
        networks->mpnet, networks->ugnet, *solver,
        presence::RemoteAvatarConfig{remote->sequence.calibration,
                                     site->remote_avatar.T_world_floor(), 1, true});
    // The EGL context the OpenXR session binds to; the views go to the swapchains.
    render::HeadlessContext context(16, 16);
    render::Renderer renderer;
    renderer.set_targets(site->target_map);
    const render::SkinnedMeshId mesh = renderer.add_skinned_mesh(avatar->mesh);
    xr::Instance instance(xr::InstanceOptions{o.headless, true, true, "deixis xr"});
    std::printf("OpenXR: %s; hand tracking %s, eye gaze %s\n", instance.description().c_str(),
                instance.features().hand_tracking ? "yes" : "no (controller poses)",
                instance.features().eye_gaze ? "yes" : "no");
    xr::GlSession session(instance);
    xr::Swapchains swapchains(instance, session);
    xr::Input input(instance, session);
    xr::FrameLoop loop(instance, session, swapchains, input);
    XrSink sink(*site, *remote, remote_avatar, renderer, mesh);
    xr::FrameLoopOptions options;
    options.seconds = o.seconds;
    const xr::FrameLoopResult result = loop.run(options, sink);
    sink.print_summary(result);
    if (result.lost) {
      std::fprintf(stderr, "deixis xr: the OpenXR session was lost\n");
      return 1;
    }
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis xr: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace deixis::app
