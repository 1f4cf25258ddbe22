// `deixis host` / `deixis join`: one site's 30 Hz loop (docs/demo.md). Setup reads the site, its
// avatar, the weights and performs the virtual user's script; then, on the steady clock, every
// tick sends the user's tracking frame, plays the remote person's frames out of the jitter buffer
// into their avatar (translator + IK), solves the user's own copy, and draws both views.

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <string>

#include "app/commands.h"
#include "app/deictic_observer.h"
#include "app/moe_weights.h"
#include "app/pose_copy.h"
#include "app/site_report.h"
#include "app/site_session.h"
#include "app/site_view.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "gesture/error.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "presence/remote_avatar.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

constexpr double kTick = 1.0 / 30.0;           // s: tracking and translation (DESIGN §3)
constexpr std::size_t kMaxCompletions = 1024;  // remote completion states kept per run
constexpr float kRayShownAbove = 0.5f;         // deictic progression above which rays show

using Networks = MoeNetworks;

// Everything a site reads and computes before it connects. Any error here is a bad input.
struct SiteAssets {
  SiteConfig site;
  avatar::Avatar avatar;
  ik::AvatarSolver solver;
  std::array<Networks, 2> networks;  // by the remote person's deictic hand
  Pose T_world_user_origin;          // the user's copy stands where the user does
  Pose T_world_remote_origin;        // the remote person's avatar
  capture::ScriptPerformance performance;
};

SiteAssets load_site(const SiteRunOptions& o) {
  SiteConfig site = read_site_config(o.site);
  if (!site.virtual_user) {
    throw Error(o.site.string() +
                ": virtual_user: missing (host and join need a scripted user; a headset front "
                "end is not part of this build)");
  }
  avatar::Avatar avatar = avatar::load_avatar(site.avatar_path);
  ik::AvatarSolver solver = ik::AvatarSolver::build(avatar.rig);
  std::array<Networks, 2> networks = {load_moe_networks(o.weights_dir, Hand::kLeft),
                                      load_moe_networks(o.weights_dir, Hand::kRight)};
  const Pose user_origin = presence::avatar_origin(solver, site.user.T_world_floor());
  const Pose remote_origin = presence::avatar_origin(solver, site.remote_avatar.T_world_floor());
  const capture::VirtualUserScene scene{site.user.T_world_floor(), site.target_map.objects,
                                        remote_origin.translation};
  capture::ScriptPerformance performance;
  try {
    const VirtualUser& user = *site.virtual_user;
    performance = capture::perform_script(capture::find_subject(user.subject), user.script, scene,
                                          user.seed, o.seconds);
  } catch (const Error& e) {
    throw Error(o.site.string() + ": " + e.what());
  }
  return {std::move(site), std::move(avatar), std::move(solver),     std::move(networks),
          user_origin,     remote_origin,     std::move(performance)};
}

net::Hello hello_of(const SiteAssets& a) {
  net::Hello h;
  h.site = a.site.site;
  h.avatar.model = "";  // the default avatar; the receiving site chooses what its avatar wears
  h.avatar.body = a.performance.sequence.calibration;
  return h;
}

// The remote person, from their hello on: their avatar in this room and their copy-paste twin.
struct Remote {
  Remote(const Networks& n, const ik::AvatarSolver& solver, const BodyCalibration& user,
         const Pose& T_world_floor, const Pose& T_world_origin)
      : copy(user, T_world_origin, solver.rig.height),
        avatar(n.mpnet, n.ugnet, solver, presence::RemoteAvatarConfig{user, T_world_floor, 1}) {}
  PoseCopy copy;
  presence::RemoteAvatar avatar;
};

// A ray from `from` through `through`, as long as the distance to `target`.
AvatarPicture with_ray(AvatarPicture picture, const Vec3& from, const Vec3& through,
                       const Vec3& target) {
  const Vec3 direction = through - from;
  if (direction.norm() > 1e-4f) {
    picture.show_ray = true;
    picture.ray_from = from;
    picture.ray_to = from + direction.normalized() * (target - from).norm();
  }
  return picture;
}

class SiteRun {
 public:
  SiteRun(const SiteRunOptions& o, SiteAssets& a, SiteSession& net, SiteView* view)
      : options_(o),
        a_(a),
        net_(net),
        view_(view),
        user_copy_(a.performance.sequence.calibration, a.solver, a.T_world_user_origin),
        observer_(kMaxCompletions) {
    const std::size_t frames = a.performance.sequence.size();
    ticks_ = o.seconds > 0.0 ? static_cast<std::uint64_t>(o.seconds / kTick + 0.5) : frames;
    record_.translation_ms.reserve(2 * ticks_ + 64);
    record_.render_ms.reserve(ticks_);
  }

  SiteRecord run(const SiteClock& clock) {
    start_ = clock.now();
    for (std::uint64_t k = 0; k < ticks_; ++k) {
      const double due = start_ + static_cast<double>(k) * kTick;
      double now = wait_until(clock, due);
      record_.late_ticks += now - due > kTick ? 1 : 0;
      tick(k, now, due);
    }
    const double end = clock.now();
    observer_.interrupt();  // a hold still in progress ends with the run
    net_.close(end);
    if (view_ != nullptr) {
      view_->finish();
    }
    return finish(end);
  }

 private:
  double wait_until(const SiteClock& clock, double due) {
    double now = clock.now();
    while (now < due) {
      net_.session().service(now, static_cast<std::uint32_t>(std::max(1.0, (due - now) * 1000.0)));
      now = clock.now();
    }
    net_.session().service(now, 0);
    return now;
  }

  // `due`: when the tick was scheduled, which is when the user's frame was sampled.
  void tick(std::uint64_t k, double now, double due) {
    const auto& frames = a_.performance.sequence.frames;
    const std::size_t i = std::min<std::size_t>(k, frames.size() - 1);
    TrackingFrame frame = frames[i];
    // Stamped with its sampling time on the sender's clock, not with when a late loop got to it:
    // ticks caught up after a stall must not go out bunched, or the other site's jitter buffer
    // plays them as a jerk (and its observer sees a completion that was not there).
    frame.time = due;
    net_.session().send_tracking(frame);
    receive(now, frame.T_world_head.translation);
    record_.visible_ticks += remote_visible() ? 1 : 0;
    user_copy_.solve(frame);
    draw(frame, a_.performance.sequence.labels[i][1]);
    ++record_.ticks;
  }

  void receive(double now, const Vec3& user_head) {
    net::Session& session = net_.session();
    if (session.state() == net::SessionState::kStreaming && session.remote_hello() != nullptr &&
        session.status().streams != remote_stream_) {
      // A new connection (the first, or after a reconnect): the person may have changed.
      const BodyCalibration& user = session.remote_hello()->avatar.body;
      remote_.emplace(a_.networks[static_cast<std::size_t>(index(user.deictic_hand))], a_.solver,
                      user, a_.site.remote_avatar.T_world_floor(), a_.T_world_remote_origin);
      remote_stream_ = session.status().streams;
      observer_.interrupt();
    }
    const LocalTargets room{&a_.site.target_map, user_head};
    net::Playout p = session.next_frame(now);
    for (; p.kind == net::PlayoutKind::kFrame || p.kind == net::PlayoutKind::kMissed;
         p = session.next_frame(now)) {
      play(p, room, now);
    }
    stream_live_ = p.kind != net::PlayoutKind::kNoStream;
    if (!stream_live_) {
      observer_.interrupt();
    }
  }

  void play(const net::Playout& p, const LocalTargets& room, double now) {
    if (!remote_) {
      return;
    }
    const TrackingFrame* frame = p.kind == net::PlayoutKind::kFrame ? p.frame : nullptr;
    const auto t0 = std::chrono::steady_clock::now();
    remote_->avatar.tick(frame, room);
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - t0;
    push(record_.translation_ms, took.count());
    if (frame != nullptr && remote_->avatar.visible()) {
      last_remote_target_ = frame->hand_target;
      const AvatarChain chain{remote_->avatar.eye_midpoint(), remote_->avatar.index_fingertip(),
                              a_.T_world_remote_origin};
      observer_.observe(*frame, p.sequence, now - start_, chain, remote_->copy, a_.site.target_map,
                        net_.session().remote_target_map());
    }
  }

  void draw(const TrackingFrame& frame, float user_deictic) {
    if (view_ == nullptr) {
      return;
    }
    AvatarPicture user{user_copy_.T_world_model(), user_copy_.model_pose()};
    const TargetObject* user_target = a_.site.target_map.find(frame.hand_target);
    if (user_target != nullptr && user_deictic > kRayShownAbove) {
      const EndEffectorPoses& copied = user_copy_.targets().deictic;
      user =
          with_ray(user, copied.T_world_head.translation, copied.index_tip, user_target->position);
    }
    std::optional<AvatarPicture> remote;
    if (remote_visible()) {
      const presence::RemoteAvatar& avatar = remote_->avatar;
      remote = AvatarPicture{avatar.T_world_model(), avatar.model_pose()};
      const TargetObject* target = a_.site.target_map.find(last_remote_target_);
      if (target != nullptr && avatar.frame().progression[1] > kRayShownAbove) {
        remote =
            with_ray(*remote, avatar.eye_midpoint(), avatar.index_fingertip(), target->position);
      }
    }
    const auto t0 = std::chrono::steady_clock::now();
    view_->draw(user, remote ? &*remote : nullptr);
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - t0;
    push(record_.render_ms, took.count());
  }

  // Hidden, never frozen: without a live stream the avatar is not shown (docs/protocol.md §8).
  bool remote_visible() const { return remote_ && stream_live_ && remote_->avatar.visible(); }

  // Within the capacity reserved at construction: the loop never allocates for its statistics.
  static void push(std::vector<double>& values, double v) {
    if (values.size() < values.capacity()) {
      values.push_back(v);
    }
  }

  SiteRecord finish(double end) {
    const net::Session& session = net_.session();
    record_.site = a_.site.site;
    record_.role = options_.host ? "host" : "join";
    record_.peer_site = session.remote_hello() ? session.remote_hello()->site : "?";
    record_.seconds = end - start_;
    record_.own_steps = a_.performance.steps;
    record_.remote_completions.assign(observer_.samples().begin(), observer_.samples().end());
    record_.completions_dropped = observer_.dropped();
    record_.net = session.stats();
    record_.strangers = session.strangers();
    record_.auth_failures = session.status().auth_failures;
    record_.jitter = session.jitter();
    record_.rejected = session.drops().total;
    record_.sealed = !options_.passphrase.empty();
    record_.traffic = net_.link().traffic();
    record_.video = view_ != nullptr ? "views.mp4" : "";
    return record_;
  }

  const SiteRunOptions& options_;
  SiteAssets& a_;
  SiteSession& net_;
  SiteView* view_;
  CopiedAvatar user_copy_;  // the user's own view: their pose copied where they stand
  std::optional<Remote> remote_;
  std::uint64_t remote_stream_ = 0;
  bool stream_live_ = false;
  TargetId last_remote_target_ = kNoTarget;
  DeicticObserver observer_;
  std::uint64_t ticks_ = 0;
  double start_ = 0.0;
  SiteRecord record_;
};

void use_site_logger(const SiteRunOptions& o, const std::string& site) {
  auto logger = spdlog::stderr_color_mt("deixis");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern(std::string("[%H:%M:%S.%e] [") + (o.host ? "host " : "join ") + site +
                      "] %v");
}

int connect_and_run(const SiteRunOptions& o, SiteAssets& assets) {
  const SiteClock clock;
  SiteSessionOptions net_options{o.host ? net::Role::kHost : net::Role::kJoiner, o.address, o.port,
                                 o.passphrase};
  SiteSession net(net_options, hello_of(assets), assets.site.target_map);
  if (o.host) {
    std::printf("port %u\n", static_cast<unsigned>(net.port()));
    std::fflush(stdout);
  }
  std::optional<SiteView> view;
  if (o.video) {
    view.emplace(assets.site, assets.avatar, o.view_width, o.view_height, o.out_dir / "views.mp4");
  }
  net.connect(clock, o.wait);
  spdlog::info("streaming with site {}", net.session().remote_hello()->site);
  SiteRun run(o, assets, net, view ? &*view : nullptr);
  const SiteRecord record = run.run(clock);
  write_site_report(record, o.out_dir / "session.json");
  print_site_summary(record, stdout);
  std::printf("wrote %s\n", (o.out_dir / "session.json").string().c_str());
  return 0;
}

}  // namespace

int run_site(const SiteRunOptions& options) {
  std::optional<SiteAssets> assets;
  try {
    assets.emplace(load_site(options));
    use_site_logger(options, assets->site.site);
    std::error_code ec;
    fs::create_directories(options.out_dir, ec);
    if (ec || !fs::is_directory(options.out_dir)) {
      throw Error(options.out_dir.string() + ": cannot create the output directory");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis %s: %s\n", options.host ? "host" : "join", e.what());
    return 2;
  }
  try {
    return connect_and_run(options, *assets);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis %s: %s\n", options.host ? "host" : "join", e.what());
    return 1;
  }
}

}  // namespace deixis::app
