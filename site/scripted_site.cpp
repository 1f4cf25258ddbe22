#include "site/scripted_site.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <type_traits>

#include "core/error.h"
#include "eval/deictic_observer.h"
#include "presence/pose_copy.h"
#include "presence/remote_avatar.h"
#include "render/image.h"
#include "site/room_peer.h"
#include "site/site_peer.h"
#include "site/site_view.h"

namespace deixis::site {

namespace {

constexpr double kTick = 1.0 / 30.0;           // s: 30 Hz (docs/conventions.md#rates-and-windows)
constexpr std::size_t kMaxCompletions = 1024;  // remote completion states kept per run
constexpr float kRayShownAbove = 0.5f;         // deictic progression above which rays show

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

// Within the capacity reserved at construction: the loop never allocates for its statistics.
void push(std::vector<double>& values, double v) {
  if (values.size() < values.capacity()) {
    values.push_back(v);
  }
}

// The remote person measured at their completion states against the avatar, and against their
// pose copied onto it (the copy-paste baseline), as the site runtime plays them.
class RemoteMeasure final : public RemotePersonWatcher {
 public:
  // `peer`: the direct session whose person is measured (null in a room, where RemotePeople
  // measures each person and this watcher hears nothing).
  RemoteMeasure(const SiteAssets& assets, SiteRecord& record, const SitePeer* peer)
      : a_(assets), record_(record), peer_(peer), observer_(kMaxCompletions) {}

  void start(double start) { start_ = start; }
  void finish() { observer_.interrupt(); }  // a hold still in progress ends with the run
  const eval::DeicticObserver& observer() const { return observer_; }
  TargetId last_target() const { return last_target_; }

  void on_new_person(const net::Hello& hello, const presence::RemoteAvatar& avatar) override {
    body_ = hello.avatar.body;
    dress(avatar.solver());
  }

  void on_played(const net::Playout& p, const presence::RemoteAvatar& avatar,
                 double translation_ms) override {
    push(record_.translation_ms, translation_ms);
    const TrackingFrame* frame = p.kind == net::PlayoutKind::kFrame ? p.frame : nullptr;
    if (&avatar.solver() != solver_) {
      dress(avatar.solver());  // they wear their own avatar now: its root, its baseline
    }
    if (frame == nullptr || !avatar.visible() || !copy_) {
      return;
    }
    last_target_ = frame->hand_target;
    const eval::AvatarChain chain = eval::chain_of(avatar);
    const net::Session& session = peer_->network().session();
    observer_.observe(*frame, p.sequence, now_ - start_, chain, *copy_, a_.site.target_map,
                      session.remote_target_map());
  }

  void on_no_stream() override { observer_.interrupt(); }

  void set_now(double now) { now_ = now; }

 private:
  // The baseline and the root for the rig the person's avatar wears (the site's, or their own
  // once it arrived, docs/avatars.md); a hold being measured ends with the avatar it was on.
  void dress(const ik::AvatarSolver& solver) {
    solver_ = &solver;
    origin_ = presence::avatar_origin(solver, a_.site.remote_avatar.T_world_floor());
    copy_.emplace(body_, origin_, solver.rig.height);
    observer_.interrupt();
  }

  const SiteAssets& a_;
  SiteRecord& record_;
  const SitePeer* peer_;
  BodyCalibration body_;
  const ik::AvatarSolver* solver_ = nullptr;
  Pose origin_;
  std::optional<presence::PoseCopy> copy_;
  eval::DeicticObserver observer_;
  TargetId last_target_ = kNoTarget;
  double start_ = 0.0;
  double now_ = 0.0;
};

// The 30 Hz loop of a scripted user, through either site runtime: a direct session (SitePeer:
// one remote person, measured here by RemoteMeasure) or a room (RoomPeer: many people, each
// measured by the room's RemotePeople).
template <class Peer>
class ScriptedSite {
  static constexpr bool kRoom = std::is_same_v<Peer, RoomPeer>;

 public:
  ScriptedSite(const SiteRunOptions& o, const SiteAssets& a, const ScriptedUser& user, Peer& peer,
               SiteView* view)
      : options_(o),
        a_(a),
        user_(user),
        peer_(peer),
        view_(view),
        user_copy_(user.body, a.solver, a.T_world_user_origin),
        measure_(a, record_, peer_measured(peer)) {
    ticks_ =
        o.seconds > 0.0 ? static_cast<std::uint64_t>(o.seconds / kTick + 0.5) : user.frames.size();
    record_.translation_ms.reserve(2 * ticks_ + 64);
    remote_pictures_.reserve(peer.people().capacity());
    record_.render_ms.reserve(ticks_);
  }

  // Services the network until the other site streams (a room: until this site is in the
  // room; the others come when they come); throws as the runtime's poll does.
  void connect(const SiteClock& clock) {
    while (!ready()) {
      const double now = clock.now();
      peer_.poll(now);
      if (!ready()) {
        peer_.wait(clock, now + 0.005);
      }
    }
  }

  SiteRecord run(const SiteClock& clock) {
    start_ = clock.now();
    measure_.start(start_);
    for (std::uint64_t k = 0; k < ticks_; ++k) {
      const double due = start_ + static_cast<double>(k) * kTick;
      peer_.wait(clock, due);
      const double now = clock.now();
      record_.late_ticks += now - due > kTick ? 1 : 0;
      tick(k, now, due);
    }
    const double end = clock.now();
    measure_.finish();
    peer_.close(end);
    if (view_ != nullptr) {
      view_->finish();
    }
    return finish(end);
  }

 private:
  bool ready() const {
    if constexpr (kRoom) {
      return peer_.in_room();
    } else {
      return peer_.streaming();
    }
  }
  // The direct session's watcher reads the session; a room measures each person itself.
  static const SitePeer* peer_measured(const Peer& peer) {
    if constexpr (kRoom) {
      return nullptr;
    } else {
      return &peer;
    }
  }

  LocalTargets room(const TrackingFrame& user) const {
    return LocalTargets{&a_.site.target_map, user.T_world_head.translation, {}};
  }

  // `due`: when the tick was scheduled, which is when the user's frame was sampled.
  void tick(std::uint64_t k, double now, double due) {
    const std::size_t i = std::min<std::size_t>(k, user_.frames.size() - 1);
    TrackingFrame frame = user_.frames[i];
    // People the script names by site become whoever of that site is here now.
    const std::vector<std::string>& names = a_.site.virtual_user->people;
    resolve_script_people(frame, names, peer_.people(), !kRoom);
    measure_.set_now(now);
    if constexpr (kRoom) {
      peer_.tick(frame, due, now, room(frame));
      // A room translates everyone due in one batch: its time is the tick's, for all of them.
      if (peer_.stats().tick_translation_ms >= 0.0) {
        push(record_.translation_ms, peer_.stats().tick_translation_ms);
      }
    } else {
      peer_.tick(frame, due, now, room(frame), &measure_);
    }
    user_copy_.solve(frame);
    draw(frame, user_.deictic[i]);
    ++record_.ticks;
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
    remote_pictures_.clear();  // capacity: one per spot, reserved at construction
    for (const DrawnAvatar& drawn : peer_.people().drawn()) {
      const presence::RemoteAvatar* avatar = drawn.avatar;
      AvatarPicture remote{avatar->T_world_model(), avatar->model_pose()};
      remote.mesh = drawn.mesh;
      remote.opacity = drawn.opacity;
      const TargetObject* target = a_.site.target_map.find(avatar->frame().hand_target);
      if (target != nullptr && avatar->frame().progression[1] > kRayShownAbove) {
        remote =
            with_ray(remote, avatar->eye_midpoint(), avatar->index_fingertip(), target->position);
      }
      remote_pictures_.push_back(remote);
    }
    const auto t0 = std::chrono::steady_clock::now();
    view_->draw(user, remote_pictures_);
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - t0;
    push(record_.render_ms, took.count());
  }

  SiteRecord finish(double end) {
    record_.site = a_.site.site;
    record_.role = options_.host ? "host" : "join";
    record_.seconds = end - start_;
    record_.own_steps = user_.steps;
    record_.sealed = !options_.passphrase.empty();
    record_.video = view_ != nullptr ? "views.mp4" : "";
    finish_network();
    return record_;
  }

  // A room: every person met, measured by the room's RemotePeople; the network figures summed.
  void finish_network() requires kRoom {
    record_.people = peer_.people().records();
    std::string sites;
    for (const PersonRecord& p : record_.people) {
      sites += (sites.empty() ? "" : ",") + p.site;
      record_.visible_ticks = std::max(record_.visible_ticks, p.visible_ticks);
    }
    record_.peer_site = sites.empty() ? "?" : sites;
    record_.room = true;
    const net::RoomSession& room = peer_.session();
    record_.net.tracking_sent = room.stats().tracking_sent;
    record_.net.parts_not_sent = room.stats().parts_not_sent;
    record_.net.send_failures = room.stats().send_failures;
    record_.auth_failures = room.stats().auth_failures;
    record_.rejected = room.drops().total;
    for (const PersonRecord& p : record_.people) {
      record_.jitter.played += p.frames_played;
      record_.jitter.missed += p.frames_missed;
    }
    record_.net.tracking_received = room.stats().tracking_received;  // people who left too
  }

  // The direct session's one remote person, measured by this site's observer.
  void finish_network() requires(!kRoom) {
    const net::Session& session = peer_.network().session();
    record_.peer_site = session.remote_hello() ? session.remote_hello()->site : "?";
    record_.visible_ticks = peer_.stats().visible_ticks;
    const eval::DeicticObserver& observer = measure_.observer();
    record_.remote_completions.assign(observer.samples().begin(), observer.samples().end());
    record_.completions_dropped = observer.dropped();
    record_.net = session.stats();
    record_.strangers = session.strangers();
    record_.auth_failures = session.status().auth_failures;
    record_.jitter = session.jitter();
    record_.rejected = session.drops().total;
    record_.traffic = peer_.network().link().traffic();
    if (session.remote_hello() != nullptr) {
      PersonRecord person;
      person.site = record_.peer_site;
      for (const PersonRecord& p : peer_.people().records()) {
        if (p.site == person.site) {
          person.avatar = p.avatar;      // what they wore last
          person.height_m = p.height_m;  // and the body their last hello described
          person.arm_length_m = p.arm_length_m;
        }
      }
      person.frames_played = peer_.stats().played;
      person.frames_missed = peer_.stats().missed;
      person.visible_ticks = peer_.stats().visible_ticks;
      person.stays = session.status().streams;
      person.completions = record_.remote_completions;
      person.completions_dropped = record_.completions_dropped;
      record_.people.push_back(std::move(person));
    }
  }

  const SiteRunOptions& options_;
  const SiteAssets& a_;
  const ScriptedUser& user_;
  Peer& peer_;
  SiteView* view_;
  presence::CopiedAvatar user_copy_;  // the user's own view: their pose copied where they stand
  SiteRecord record_;
  RemoteMeasure measure_;
  std::vector<AvatarPicture> remote_pictures_;  // this tick's visible remote avatars
  std::uint64_t ticks_ = 0;
  double start_ = 0.0;
};

}  // namespace

SiteAssets load_site_assets(SiteConfig site, const std::filesystem::path& weights_dir) {
  avatar::Avatar avatar = avatar::load_avatar(site.avatar_path);
  ik::AvatarSolver solver = ik::AvatarSolver::build(avatar.rig);
  std::array<MoeNetworks, 2> networks = {load_moe_networks(weights_dir, Hand::kLeft),
                                         load_moe_networks(weights_dir, Hand::kRight)};
  const Pose user_origin = presence::avatar_origin(solver, site.user.T_world_floor());
  const Pose remote_origin = presence::avatar_origin(solver, site.remote_avatar.T_world_floor());
  return {std::move(site), std::move(avatar), std::move(solver), std::move(networks),
          user_origin,     remote_origin,     WornAvatars{}};
}

void load_run_avatars(SiteAssets& assets, const SiteRunOptions& o) {
  assets.worn = load_worn_avatars(o.avatar, o.remote_avatar);
}

namespace {

template <class Peer>
SiteRecord run_loop(const SiteRunOptions& o, const SiteAssets& assets, const ScriptedUser& user,
                    const SiteClock& clock, Peer& peer) {
  std::optional<SiteView> view;
  if (o.video) {
    view.emplace(assets.site, assets.avatar, o.view_width, o.view_height, o.out_dir / "views.mp4");
  }
  ScriptedSite<Peer> site(o, assets, user, peer, view ? &*view : nullptr);
  site.connect(clock);
  const SiteRecord record = site.run(clock);
  if (view) {
    // The last frame as a still: what each person wore at the end, for a look (or a test).
    render::write_png(view->frame(), o.out_dir / "views.png");
  }
  write_site_report(record, o.out_dir / "session.json");
  print_site_summary(record, stdout);
  std::printf("wrote %s\n", (o.out_dir / "session.json").string().c_str());
  return record;
}

}  // namespace

SiteRecord run_scripted_site(const SiteRunOptions& o, const SiteAssets& assets,
                             const ScriptedUser& user) {
  if (user.frames.empty() || user.deictic.size() != user.frames.size()) {
    throw Error(o.site.string() + ": the scripted user performed no frames");
  }
  const SiteClock clock;
  if (!o.room.empty()) {
    RoomPeerOptions room;
    room.relay_host = o.address;
    room.relay_port = o.port;
    room.room = o.room;
    room.passphrase = o.passphrase;
    room.wait = o.wait;
    room.drop_tracking = o.drop_tracking;
    room.people.completions = kMaxCompletions;
    room.people.override_avatar = assets.worn.override_avatar;
    room.avatar_file = assets.worn.own_file;
    room.chosen_avatars = true;  // this loop draws each person in what they wear
    room.avatar_cache = AvatarCache::default_dir();
    RoomPeer peer(room, assets.site, user.body, assets.networks, assets.solver, clock.now());
    return run_loop(o, assets, user, clock, peer);
  }
  SitePeerOptions peer_options{o.host ? net::Role::kHost : net::Role::kJoiner, o.address, o.port,
                               o.passphrase, o.wait};
  peer_options.people.override_avatar = assets.worn.override_avatar;
  peer_options.avatar_file = assets.worn.own_file;
  peer_options.chosen_avatars = true;
  peer_options.avatar_cache = AvatarCache::default_dir();
  SitePeer peer(peer_options, assets.site, user.body, assets.networks, assets.solver, clock.now());
  if (o.host) {
    std::printf("port %u\n", static_cast<unsigned>(peer.port()));
    std::fflush(stdout);
  }
  return run_loop(o, assets, user, clock, peer);
}

}  // namespace deixis::site
