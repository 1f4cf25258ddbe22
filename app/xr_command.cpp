// `deixis xr`: the headset user's side through OpenXR (docs/xr.md). Each frame the headset
// user's tracking is read from the runtime and both eyes see this room, its objects and the
// remote people's avatars. The remote person is either another site (--host / --join: the user's
// tracking goes out at 30 Hz with targets selected from it), everyone else in a room on a relay
// (--connect --room: each on one of this site's avatar spots, and each a target), both through
// site::LivePeer (site/live_peer.h), or, without a network, the other site's scripted virtual
// user performed locally; either way presence::RemoteAvatar translates them into this room at
// 30 Hz of display time.

#include <cstdio>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/xr_setup.h"
#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "gesture/target_selection.h"
#include "gesture/upright_calibration.h"
#include "ik/avatar_solver.h"
#include "presence/remote_avatar.h"
#include "render/mesh_cache.h"
#include "render/renderer.h"
#include "site/live_peer.h"
#include "site/moe_weights.h"
#include "site/presence_panel.h"
#include "site/recorded_user.h"
#include "site/room_setup.h"
#include "site/site_config.h"
#include "site/site_session.h"
#include "xr/blend_mode.h"
#include "xr/frame_loop.h"
#include "xr/gl_context.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

constexpr double kTick = 1.0 / 30.0;  // s: translation rate (docs/conventions.md#rates-and-windows)

using Networks = site::MoeNetworks;

// The remote person: the other site's virtual user performed in their room.
capture::ScriptPerformance perform_remote(const site::SiteConfig& remote,
                                          const ik::AvatarSolver& solver, const fs::path& source,
                                          double seconds) {
  if (!remote.virtual_user) {
    throw Error(source.string() +
                ": virtual_user: missing (the remote person is this site's scripted user)");
  }
  if (remote.virtual_user->recording) {  // docs/bvh.md#driving-a-site
    site::ScriptedUser user = site::play_recorded_user(remote, seconds);
    return capture::unscripted_performance(user.body, std::move(user.frames));
  }
  const Pose partner = presence::avatar_origin(solver, remote.remote_avatar.T_world_floor());
  const capture::VirtualUserScene scene{remote.user.T_world_floor(), remote.target_map.objects,
                                        partner.translation};
  try {
    const site::VirtualUser& user = *remote.virtual_user;
    return capture::perform_script(capture::find_subject(user.subject), user.script, scene,
                                   user.seed, seconds);
  } catch (const Error& e) {
    throw Error(source.string() + ": " + e.what());
  }
}

// The remote person when there is no network: the other site's script, performed locally and
// translated tick by tick.
struct LocalRemote {
  const capture::ScriptPerformance& performance;
  presence::RemoteAvatar& avatar;
};

// What a networked headset site needs to meet the other site once its user is calibrated.
struct NetworkSetup {
  site::LivePeerOptions options;
  UprightBody body;
  const std::array<Networks, 2>* networks = nullptr;
  const ik::AvatarSolver* solver = nullptr;
  const site::WornAvatars* worn = nullptr;  // the user's choice offered, the local override
};

// Joins the OpenXR frame loop to the translator and the renderer; allocates nothing per frame
// once the remote people are there (meeting one builds their avatar once).
class XrSink final : public xr::FrameSink {
 public:
  // `mesh`: what remote people wear unless they wear their own.
  // `see_through`: the headset shows the real room (xr/blend_mode.h), so only avatars are drawn.
  // `panel`: the head-locked presence panel is shown while networked.
  XrSink(const site::SiteConfig& site, render::Renderer& renderer, const avatar::SkinnedMesh& mesh,
         const Vec3& remote_head_at_rest, bool see_through, bool panel)
      : site_(site),
        renderer_(renderer),
        see_through_(see_through),
        show_panel_(panel),
        meshes_(renderer, mesh),
        remote_head_(remote_head_at_rest) {
    avatars_.reserve(site.spots.size());  // one per spot: every remote person at once
  }

  void use_local(const LocalRemote& local) { local_.emplace(local); }
  void use_network(const NetworkSetup& setup) { network_ = setup; }

  void on_frame(const xr::FrameInfo& frame, const TrackingFrame& user) override {
    if (failed_) {
      return;
    }
    count_tracking(user);
    try {
      if (network_) {
        networked_frame(frame, user);
      } else {
        local_frame(frame);
      }
    } catch (const std::exception& e) {
      // Ends the session through the lifecycle (wants_exit) rather than unwinding mid-frame.
      error_ = e.what();
      failed_ = true;
    }
  }

  void render_view(std::uint32_t, const render::Camera& camera,
                   const render::RenderTarget& target) override {
    render::SceneView view;
    view.camera = camera;
    view.show_floor = !see_through_;
    view.show_targets = !see_through_;
    avatars_.clear();
    for (const site::DrawnAvatar& drawn : shown_avatars()) {
      // Their choice, the override, else the site's; not drawn when more different avatars came
      // than the cache holds.
      const std::optional<render::SkinnedMeshId> mesh = meshes_.get(drawn.mesh);
      if (mesh && avatars_.size() < avatars_.capacity()) {
        avatars_.push_back(
            {*mesh, drawn.avatar->T_world_model(), drawn.avatar->model_pose(), drawn.opacity});
      }
    }
    view.avatars = avatars_;
    if (peer_ && show_panel_) {
      // Head-locked: below the line of sight, facing the eyes (docs/xr.md "Presence panel").
      head_panel_.T_world_panel = compose(user_head_pose_, kHeadPanel);
      head_panel_.lines = panel_.lines();
      head_panel_.line_height = kPanelLineHeight;
      view.panel = &head_panel_;
    }
    renderer_.render(view, target);
  }

  bool wants_exit() const override { return failed_; }
  const std::string& error() const { return error_; }

  // Says bye; who was there at the end is kept for the summary.
  void close(double now) {
    if (!peer_) {
      return;
    }
    panel_.update(now, *peer_, true);
    panel_lines_.assign(panel_.lines().begin(), panel_.lines().end());
    std::array<site::LivePerson, 16> people;
    const std::size_t n = peer_->list_people(people);
    for (std::size_t k = 0; k < n; ++k) {
      people_.push_back({std::string(people[k].site), people[k].frames_played,
                         people[k].visible_ticks, std::string(people[k].avatar),
                         people[k].avatar_joints});
    }
    peer_->close(now);
  }

  // `gaze_from_head`: frames whose gaze was estimated as the head's forward (xr/input.h).
  void print_summary(const xr::FrameLoopResult& r, std::uint64_t gaze_from_head) const {
    std::printf(
        "frames %llu, views rendered %llu, translation ticks %llu (avatar visible in %llu)\n"
        "headset user tracked: head %llu, gaze %llu (estimated from the head in %llu), left hand "
        "%llu, right hand %llu frames\n"
        "session: focused in %llu frames\n",
        static_cast<unsigned long long>(r.frames),
        static_cast<unsigned long long>(r.rendered_views), static_cast<unsigned long long>(ticks_),
        static_cast<unsigned long long>(visible_ticks_),
        static_cast<unsigned long long>(valid_counts_[0]),
        static_cast<unsigned long long>(valid_counts_[1]),
        static_cast<unsigned long long>(gaze_from_head),
        static_cast<unsigned long long>(valid_counts_[2]),
        static_cast<unsigned long long>(valid_counts_[3]),
        static_cast<unsigned long long>(r.focused_frames));
    if (peer_) {
      const site::LivePeerStats& n = peer_->stats();
      std::printf("network: site %s, tracking sent %llu, frames played %llu (%llu missed)\n",
                  n.peer_site.c_str(), static_cast<unsigned long long>(n.sent),
                  static_cast<unsigned long long>(n.played),
                  static_cast<unsigned long long>(n.missed));
      for (const PersonLine& p : people_) {
        std::printf(
            "person %s: frames played %llu, visible in %llu ticks, wearing %s (%d joints)\n",
            p.site.c_str(), static_cast<unsigned long long>(p.frames_played),
            static_cast<unsigned long long>(p.visible_ticks), p.avatar.c_str(), p.avatar_joints);
      }
      for (const std::string& line : panel_lines_) {  // the presence panel as it was last
        std::printf("panel: %s\n", line.c_str());
      }
    }
  }

 private:
  void count_tracking(const TrackingFrame& user) {
    if ((user.valid & tracked::kHead) != 0) {
      user_head_ = user.T_world_head.translation;
      user_head_pose_ = user.T_world_head;
    }
    for (std::size_t part = 0; part < valid_counts_.size(); ++part) {
      valid_counts_[part] += (user.valid & (1u << part)) != 0 ? 1 : 0;
    }
  }

  void local_frame(const xr::FrameInfo& frame) {
    const auto& frames = local_->performance.sequence.frames;
    const LocalTargets room{&site_.target_map, user_head_};
    while (static_cast<double>(ticks_) * kTick <= frame.seconds && !frames.empty()) {
      const std::size_t i = std::min<std::size_t>(ticks_, frames.size() - 1);
      TrackingFrame f = frames[i];
      f.time = static_cast<double>(ticks_) * kTick;
      visible_ticks_ += local_->avatar.tick(&f, room) ? 1 : 0;
      ++ticks_;
    }
  }

  void networked_frame(const xr::FrameInfo& frame, const TrackingFrame& user) {
    if (!peer_) {
      if ((user.valid & tracked::kHead) == 0) {
        return;  // calibration waits for the head
      }
      meet(user, frame.seconds);
    } else if (recalibrate_pressed(frame.buttons, network_->body.deictic_hand) &&
               (user.valid & tracked::kHead) != 0) {
      recalibrate(user);
    }
    while (static_cast<double>(ticks_) * kTick <= frame.seconds) {
      // The user designates what they look and point at in this room; the other person (in a
      // room: everyone) is where their avatar's eyes are.
      TrackingFrame out = user;
      selector_.select(out, peer_->candidates(site_.target_map, user_head_, remote_head_));
      const LocalTargets room{&site_.target_map, user_head_};
      // Stamped with its sampling time (display time on the wall clock), not with when this
      // frame's loop got to it: a late frame catching up on several ticks must not send them
      // bunched together, or the other site's jitter buffer plays them as a jerk.
      const double sampled = wall_at_first_frame_ + static_cast<double>(ticks_) * kTick;
      peer_->tick(out, sampled, sampled, room);
      visible_ticks_ += peer_->visible().empty() ? 0 : 1;
      ++ticks_;
    }
    if (peer_) {
      panel_.update(frame.seconds, *peer_);
    }
  }

  // The user stands upright when the session starts: their calibration goes in the hello.
  void meet(const TrackingFrame& upright, double display_seconds) {
    wall_at_first_frame_ = clock_.now() - display_seconds;
    const BodyCalibration calibration = calibrate_and_tell(upright, network_->body, false);
    selector_.config = target_selection_for(calibration);
    peer_.emplace(network_->options, site_, calibration, *network_->networks, *network_->solver,
                  *network_->worn, clock_.now());
    if (peer_->port() != 0) {  // a host
      std::printf("port %u\n", static_cast<unsigned>(peer_->port()));
    }
    std::fflush(stdout);
  }

  // The recalibrate button (app/xr_setup.h): the user's upright posture again, sent to the people
  // met in a new hello (their avatar of this user starts afresh from it).
  void recalibrate(const TrackingFrame& upright) {
    const BodyCalibration calibration = calibrate_and_tell(upright, network_->body, true);
    selector_.config = target_selection_for(calibration);
    peer_->set_user(site_, calibration);
  }

  // The networked people's avatars (fading ones too), else the headset user's own translated.
  std::span<const site::DrawnAvatar> shown_avatars() {
    if (peer_) {
      return peer_->drawn();
    }
    if (!local_ || !local_->avatar.visible()) {
      return {};
    }
    local_shown_ = site::DrawnAvatar{&local_->avatar, nullptr, 1.0f};
    return std::span(&local_shown_, 1);
  }

  struct PersonLine {
    std::string site;
    std::uint64_t frames_played = 0, visible_ticks = 0;
    std::string avatar;
    int avatar_joints = 0;
  };

  const site::SiteConfig& site_;
  render::Renderer& renderer_;
  bool see_through_;
  bool show_panel_;
  render::SkinnedMeshCache meshes_;  // the site's avatar and those people chose, uploaded once
  Vec3 remote_head_;
  std::optional<LocalRemote> local_;
  std::optional<NetworkSetup> network_;
  std::optional<site::LivePeer> peer_;
  std::vector<PersonLine> people_;  // who was there when the session closed
  site::DrawnAvatar local_shown_{};
  TargetSelector selector_;
  site::SiteClock clock_;
  double wall_at_first_frame_ = 0.0;         // the wall clock at display time 0
  std::vector<render::AvatarDraw> avatars_;  // this view's, one per spot at most
  Vec3 user_head_ = Vec3(0, 1.6f, 0);
  Pose user_head_pose_{};
  site::PresencePanel panel_;
  render::HeadPanel head_panel_;
  std::vector<std::string> panel_lines_;  // the panel's last lines, for the summary
  std::uint64_t ticks_ = 0;
  std::uint64_t visible_ticks_ = 0;
  std::array<std::uint64_t, 4> valid_counts_{};  // head, gaze, left hand, right hand
  bool failed_ = false;
  std::string error_;
};

// Everything read before OpenXR starts; any error here is a bad input (exit 2).
struct XrAssets {
  site::SiteConfig site;
  avatar::Avatar avatar;
  ik::AvatarSolver solver;
  std::array<Networks, 2> networks;                  // by the remote person's deictic hand
  std::optional<capture::ScriptPerformance> remote;  // without a network
  site::WornAvatars worn;  // --avatar offered to the people met, --remote-avatar worn here
};

Hand xr_hand(const XrRunOptions& o) {
  return o.hand == "left" ? Hand::kLeft : Hand::kRight;
}

XrAssets load_assets(const XrRunOptions& o) {
  site::SiteConfig site = site::read_site_config(o.site);
  for (const site::BehindSpot& b : site::behind_spots(site)) {
    std::fprintf(stderr, "deixis xr: warning: %s\n", site::describe(site, b).c_str());
  }
  avatar::Avatar avatar = avatar::load_avatar(site.avatar_path);
  ik::AvatarSolver solver = ik::AvatarSolver::build(avatar.rig);
  std::array<Networks, 2> networks = {site::load_moe_networks(o.weights_dir, Hand::kLeft),
                                      site::load_moe_networks(o.weights_dir, Hand::kRight)};
  std::optional<capture::ScriptPerformance> remote;
  if (!o.network) {
    remote =
        perform_remote(site::read_site_config(o.remote_site), solver, o.remote_site, o.seconds);
  }
  return {std::move(site),   std::move(avatar),
          std::move(solver), std::move(networks),
          std::move(remote), site::load_worn_avatars(o.avatar, o.remote_avatar)};
}

// The headset: the OpenXR instance (with the blend mode chosen), the GL context the session
// binds to (EGL, else a hidden GLFW window's GLX context: xr/gl_context.h), the renderer, the
// session, its swapchains, input and frame loop, made in that order.
struct Headset {
  explicit Headset(const XrRunOptions& o)
      : instance(xr::InstanceOptions{o.headless, true, true, "deixis xr",
                                     *xr::parse_blend_choice(o.blend)}),
        blend(instance.view_config().blend_mode),
        see_through(xr::see_through(blend)),
        context(xr::make_gl_context(instance)),
        // See-through: cleared to transparent black, which ALPHA_BLEND shows as the real room
        // and ADDITIVE adds nothing to.
        renderer(see_through ? render::RendererOptions{.background = render::Colour(0, 0, 0, 0)}
                             : render::RendererOptions{}),
        session(instance),
        swapchains(instance, session),
        input(instance, session),
        loop(instance, session, swapchains, input) {
    std::printf("OpenXR: %s; hand tracking %s, eye gaze %s\n", instance.description().c_str(),
                instance.features().hand_tracking ? "yes" : "no (controller poses)",
                instance.features().eye_gaze ? "yes" : "no (the head's forward, estimated)");
    std::printf("blend mode %s%s\n", xr::blend_mode_name(blend),
                see_through ? " (see-through: the avatars only, over the real room)"
                            : " (the virtual room)");
  }

  // Runs the frame loop; returns 1 when the session was lost, else 0.
  int run(double seconds, xr::FrameSink& sink, xr::FrameLoopResult& result) {
    xr::FrameLoopOptions options;
    options.seconds = seconds;
    result = loop.run(options, sink);
    if (result.lost) {
      std::fprintf(stderr, "deixis xr: the OpenXR session was lost\n");
      return 1;
    }
    return 0;
  }

  xr::Instance instance;
  XrEnvironmentBlendMode blend;
  bool see_through;
  std::unique_ptr<render::Context> context;
  render::Renderer renderer;
  xr::GlSession session;
  xr::Swapchains swapchains;
  xr::Input input;
  xr::FrameLoop loop;
};

int run_session(const XrRunOptions& o, XrAssets& a) {
  const Pose remote_floor = a.site.remote_avatar.T_world_floor();
  // Without a network the remote person wears the override (--remote-avatar) if there is one.
  const site::PersonAvatar* override_avatar = a.worn.override_avatar.get();
  const ik::AvatarSolver& local_solver = override_avatar ? override_avatar->solver : a.solver;
  std::optional<presence::RemoteAvatar> local_avatar;
  if (a.remote) {
    const BodyCalibration& person = a.remote->sequence.calibration;
    const Networks& n =
        a.networks[static_cast<std::size_t>(index(site::translating_weights(person.deictic_hand)))];
    local_avatar.emplace(
        n.mpnet, n.ugnet, local_solver,
        presence::RemoteAvatarConfig{.user = person,
                                     .T_world_floor = remote_floor,
                                     .mirrored = site::translated_mirrored(person.deictic_hand)});
  }
  Headset headset(o);
  headset.renderer.set_targets(a.site.target_map);
  const avatar::SkinnedMesh& mesh =
      local_avatar && override_avatar ? override_avatar->avatar.mesh : a.avatar.mesh;
  XrSink sink(a.site, headset.renderer, mesh,
              presence::avatar_origin(local_solver, remote_floor).translation, headset.see_through,
              !o.no_panel);
  if (local_avatar) {
    sink.use_local({*a.remote, *local_avatar});
  } else {
    sink.use_network(
        {site::live_peer_options(o.host, o.address, o.port, o.room, o.passphrase, o.wait),
         UprightBody{xr_hand(o), o.height, 0}, &a.networks, &a.solver, &a.worn});
  }
  xr::FrameLoopResult result;
  const int status = headset.run(o.seconds, sink, result);
  sink.close(0.0);
  sink.print_summary(result, headset.input.gaze_from_head_frames());
  if (!sink.error().empty()) {
    std::fprintf(stderr, "deixis xr: %s\n", sink.error().c_str());
    return 1;
  }
  return status;
}

// What `--setup` reads before OpenXR starts: the site, and its map ready to edit (a map without
// objects is refused there, naming the file).
struct SetupAssets {
  site::SiteConfig site;
  site::RoomSetup setup;
};

SetupAssets load_setup(const XrRunOptions& o) {
  site::SiteConfig site = site::read_site_config(o.site);
  site::RoomSetup setup(site.target_map, xr_hand(o), site.target_map_path.string());
  return {std::move(site), std::move(setup)};
}

// `--setup`: the room's target map set up from inside the headset (app/xr_setup.h); no network.
int run_setup(const XrRunOptions& o, SetupAssets& a) {
  Headset headset(o);
  const std::filesystem::path save = o.save.empty() ? a.site.target_map_path : o.save;
  std::printf("setting up %s (%zu objects), saving to %s\n",
              a.site.target_map_path.string().c_str(), a.site.target_map.objects.size(),
              save.string().c_str());
  std::fflush(stdout);
  SetupSink sink(std::move(a.setup), save, UprightBody{xr_hand(o), o.height, 0}, headset.renderer,
                 headset.see_through, !o.no_panel);
  xr::FrameLoopResult result;
  const int status = headset.run(o.seconds, sink, result);
  const bool all_saved = sink.print_summary();
  return status != 0 ? status : (all_saved ? 0 : 1);
}

// Reads what the run needs (a bad flag's file or a bad file: exit 2), then runs it (OpenXR or
// the network failing: exit 1).
template <class Load, class Run>
int load_then_run(const Load& load, const Run& run) {
  std::optional<decltype(load())> assets;
  try {
    assets.emplace(load());
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis xr: %s\n", e.what());
    return 2;
  }
  try {
    return run(*assets);
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis xr: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int run_xr(const XrRunOptions& o) {
  if (o.setup) {
    return load_then_run([&] { return load_setup(o); },
                         [&](SetupAssets& a) { return run_setup(o, a); });
  }
  return load_then_run([&] { return load_assets(o); },
                       [&](XrAssets& a) { return run_session(o, a); });
}

}  // namespace deixis::app
