// `deixis sim`: the desktop simulator (docs/sim.md). One window, both sites in this process: on
// the left the local room (site A) with the virtual user, drawn as an avatar copying the user's
// pose; on the right the remote room (site B) with the avatar presence::RemoteAvatar translates
// the user's tracking into, at 30 Hz; below, the ImGui panel. The mouse and keys drive the user
// (or the site's script does) and move B's objects; the avatar adapts on the next tick.
// With --host / --join, or from the panel's network form, the simulator is site A of a real
// session (sim/sim_network.h): the user streams to the other site, whose person stands in the
// left view where A's remote avatar does; the right view keeps the local translation into B as a
// preview. With --connect --room it is a member of a room on a relay: everyone else in the room
// stands on A's avatar spots in the left view, and the user may look and point at them.

#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "avatar/avatar_loader.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "core/script_step.h"
#include "presence/pose_copy.h"
#include "presence/remote_avatar.h"
#include "render/image.h"
#include "render/mesh_cache.h"
#include "render/window_context.h"
#include "sim/sim_controls.h"
#include "sim/sim_history.h"
#include "sim/sim_imgui.h"
#include "sim/sim_network.h"
#include "sim/sim_network_form.h"
#include "sim/sim_panel.h"
#include "sim/sim_time.h"
#include "sim/sim_user.h"
#include "sim/sim_views.h"
#include "site/moe_weights.h"
#include "site/recorded_user.h"
#include "site/remote_people.h"

namespace deixis::sim {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kTick = SimTime::kTick;     // s: 30 Hz (docs/conventions.md#rates-and-windows)
constexpr double kScriptMinSeconds = 300.0;  // a --script user's performance, at least
constexpr float kRayShownAbove = 0.5f;       // deictic progression above which rays show
constexpr int kMaxTicksPerFrame = 5;         // a stalled frame does not snowball
constexpr std::uint64_t kDefaultSeed = 1;
// Start's tooltip in a --fixed-step run (decision 50).
constexpr std::string_view kNoSessionWhenFixed =
    "--fixed-step: one tick per frame, but a session runs on the wall clock (the other site's). "
    "Run without --fixed-step to start one.";

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The site's virtual user's subject and seed, or the demo's site-A subject (also when the
// virtual user is a recording: the mouse drives a synthetic person).
const capture::Subject& user_subject(const site::SiteConfig& a) {
  const bool named = a.virtual_user && !a.virtual_user->subject.empty();
  return capture::find_subject(named ? a.virtual_user->subject : "172");
}

// --script with a recording (docs/bvh.md#driving-a-site): its person on A's user spot at 30 Hz, as
// host and join play it; a performance without labels, since a recording designates nothing.
capture::ScriptPerformance recorded_performance(const site::SiteConfig& a, double seconds) {
  site::ScriptedUser user = site::play_recorded_user(a, seconds);
  return capture::unscripted_performance(user.body, std::move(user.frames));
}

// The avatar standing in the remote room and the translator + IK that drive it. Rebuilt when the
// person loads another avatar (the solver must stay where the RemoteAvatar points).
struct RemoteSide {
  RemoteSide(const fs::path& glb, const BodyCalibration& user, const site::MoeNetworks& networks,
             const site::SiteConfig& room)
      : path(glb),
        avatar(avatar::load_avatar(glb)),
        solver(ik::AvatarSolver::build(avatar.rig)),
        remote(networks.mpnet, networks.ugnet, solver,
               presence::RemoteAvatarConfig{
                   .user = user,
                   .T_world_floor = room.remote_avatar.T_world_floor(),
                   .mirrored = site::translated_mirrored(user.deictic_hand)}) {}
  fs::path path;
  avatar::Avatar avatar;
  ik::AvatarSolver solver;
  presence::RemoteAvatar remote;
  render::SkinnedMeshId mesh;
};

// Everything read before the window opens; any error here is a bad input (exit 2).
struct SimAssets {
  site::SiteConfig a;
  site::SiteConfig b;
  avatar::Avatar user_avatar;
  std::optional<ik::AvatarSolver> user_solver;
  std::optional<site::MoeNetworks> networks;  // the user's hand: the preview in B
  std::optional<std::array<site::MoeNetworks, 2>>
      peer_networks;              // by the other's hand; none when
                                  // no session can start (--fixed-step)
  std::unique_ptr<SimUser> user;  // null with --script
  std::optional<capture::ScriptPerformance> script;
  std::optional<ScriptedInput> input;
  BodyCalibration calibration;
  fs::path remote_avatar_path;
  site::WornAvatars worn;  // --avatar offered to the people met, --remote-avatar worn by them here
};

SimAssets load_assets(const sim::SimOptions& o) {
  SimAssets s;
  s.a = site::read_site_config(o.site_a);
  s.b = site::read_site_config(o.site_b);
  for (const site::SiteConfig* room : {&s.a, &s.b}) {
    for (const site::BehindSpot& b : site::behind_spots(*room)) {
      std::fprintf(stderr, "deixis sim: warning: %s\n", site::describe(*room, b).c_str());
    }
  }
  s.user_avatar = avatar::load_avatar(s.a.avatar_path);
  s.user_solver = ik::AvatarSolver::build(s.user_avatar.rig);
  const Pose partner = presence::avatar_origin(*s.user_solver, s.a.remote_avatar.T_world_floor());
  if (o.script) {
    if (!s.a.virtual_user) {
      throw Error(o.site_a.string() + ": virtual_user: missing (--script plays it)");
    }
    const site::VirtualUser& v = *s.a.virtual_user;
    if (v.recording) {
      s.script = recorded_performance(s.a, std::max(o.seconds, kScriptMinSeconds));
    } else {
      // The k-th person the script names is aimed at where the avatar on spot k stands; each tick
      // the target becomes whoever of that site is here (site/remote_people.h), as for host/join.
      std::vector<capture::ScenePerson> people;
      for (std::size_t k = 0; k < v.people.size(); ++k) {
        people.push_back({v.people[k], script_person_target(k),
                          site::expected_person_head(s.a, *s.user_solver, k)});
      }
      const capture::VirtualUserScene scene{s.a.user.T_world_floor(), s.a.target_map.objects,
                                            partner.translation, people};
      try {
        s.script = capture::perform_script(capture::find_subject(v.subject), v.script, scene,
                                           v.seed, std::max(o.seconds, kScriptMinSeconds));
      } catch (const Error& e) {
        throw Error(o.site_a.string() + ": " + e.what());
      }
    }
    s.calibration = s.script->sequence.calibration;
  } else {
    const std::uint64_t seed = s.a.virtual_user ? s.a.virtual_user->seed : kDefaultSeed;
    s.user = std::make_unique<SimUser>(
        user_subject(s.a),
        SimUserScene{s.a.user.T_world_floor(), s.a.target_map.objects, partner.translation}, seed);
    s.calibration = s.user->calibration();
  }
  s.networks.emplace(site::load_moe_networks(
      o.weights_dir, site::translating_weights(s.calibration.deictic_hand)));
  if (!o.fixed_step) {  // the flags' session, or one the panel may start
    s.peer_networks.emplace(
        std::array<site::MoeNetworks, 2>{site::load_moe_networks(o.weights_dir, Hand::kLeft),
                                         site::load_moe_networks(o.weights_dir, Hand::kRight)});
  }
  if (!o.input.empty()) {
    s.input.emplace(read_input_script(o.input));
  }
  s.remote_avatar_path = o.avatar.empty() ? s.b.avatar_path : o.avatar;
  s.worn = site::load_worn_avatars(o.avatar, o.remote_avatar);
  return s;
}

// A ray from `from` through `through`, as long as the distance to `target`.
render::DebugLine eye_ray(const Vec3& from, const Vec3& through, const Vec3& target) {
  render::DebugLine line;
  const Vec3 direction = through - from;
  line.from = from;
  line.to = direction.norm() > 1e-4f ? Vec3(from + direction.normalized() * (target - from).norm())
                                     : from;
  return line;
}

class Sim {
 public:
  Sim(const sim::SimOptions& o, SimAssets& a, render::WindowContext& window)
      : o_(o),
        a_(a),
        window_(window),
        remote_map_(a.b.target_map),
        local_(a.a, a.a.target_map),
        remote_view_(a.b, remote_map_),
        user_copy_(a.calibration, *a.user_solver,
                   presence::avatar_origin(*a.user_solver, a.a.user.T_world_floor())),
        local_meshes_(local_.renderer(), a.user_avatar.mesh),
        controls_(local_, remote_view_, a.a.target_map, remote_map_, a.user.get()),
        imgui_(window.glfw_window()),
        window_input_(window.glfw_window()),
        time_(fixed_step()) {
    remote_ = make_remote(a.remote_avatar_path);
    const fs::path& glb = a.remote_avatar_path;
    std::snprintf(edits_.avatar_path.data(), edits_.avatar_path.size(), "%s",
                  o.avatar.empty() ? "" : glb.c_str());
    // The remote avatar looks at the person in B's room: where B's user stands.
    b_partner_head_ =
        presence::avatar_origin(remote_->solver, a.b.user.T_world_floor()).translation;
    edits_.network = initial_network_form(o);
    find_widget_ = [this](std::string_view label) { return widget_centre(label); };
    // Room A's view draws the user's copy and everyone on its spots, each with a ray.
    avatars_.reserve(1 + a.a.spots.size());
    lines_.reserve(1 + a.a.spots.size());
    if (o.network) {
      start_network(
          site::live_peer_options(o.host, o.address, o.port, o.room, o.passphrase, o.wait));
    }
  }

  int run() {
    for (std::uint64_t frame = 0;; ++frame) {
      const Clock::time_point frame_start = Clock::now();
      window_.poll_events();
      const double t = time_.next_frame();
      const bool last = (o_.frames > 0 && frame + 1 >= o_.frames) ||
                        (o_.seconds > 0.0 && t + (time_.fixed() ? kTick : 0.0) >= o_.seconds);
      if (!step(t, last)) {
        break;
      }
      history_.frame_ms.push(static_cast<float>(ms_since(frame_start)));
      frames_ = frame + 1;
      if (last || window_.should_close()) {
        break;
      }
    }
    return finish();
  }

 private:
  // The other site follows the wall clock, so a networked simulator does too (a session started
  // from the panel switches time_ to it).
  bool fixed_step() const { return !o_.network && (o_.fixed_step || a_.input.has_value()); }

  // A session, from the flags or the panel's form: the same site::LivePeer start, which never
  // blocks (a host binds, a joiner or room member sends its first packet; connecting is polled
  // tick by tick). The other people wear A's avatar, as the user's copy does.
  void start_network(const site::LivePeerOptions& options) {
    network_.reset();  // the last session, failed or left
    form_problem_.clear();
    network_.emplace(options, a_.a, a_.calibration, *a_.peer_networks, *a_.user_solver, a_.worn);
    network_panel_ = network_->panel();
    time_.follow_wall_clock();
  }

  void start_from_form() {
    const FormSession session = form_session(edits_.network);
    if (session.room) {
      start_network(*session.room);
    } else if (session.options) {
      start_network(*session.options);
    } else {
      form_problem_ = session.problem;
    }
  }

  void leave_network() {
    network_->close();
    network_panel_ = network_->panel();
  }

  // Where scripted clicks aimed at a panel widget go: its centre in the last frame drawn.
  std::optional<render::Vec2> widget_centre(std::string_view label) const {
    const PanelWidgets::Item* item = widgets_.find(label);
    if (item == nullptr) {
      return std::nullopt;
    }
    return render::Vec2(0.5f * (item->x0 + item->x1), 0.5f * (item->y0 + item->y1));
  }

  std::unique_ptr<RemoteSide> make_remote(const fs::path& glb) {
    auto side = std::make_unique<RemoteSide>(glb, a_.calibration, *a_.networks, a_.b);
    side->mesh = remote_view_.renderer().add_skinned_mesh(side->avatar.mesh);
    return side;
  }

  // One frame at simulator time t; false when the person asked to quit.
  bool step(double t, bool last) {
    const render::RenderTarget window = window_.target();
    const SimLayout layout = sim_layout(window.width, window.height);
    local_.place(layout.local);
    remote_view_.place(layout.remote);
    const FrameInput in = a_.input ? a_.input->next(t, find_widget_) : window_input_.next();
    imgui_.begin_frame(a_.input ? &in : nullptr);
    const PanelActions actions = draw_panel(layout.panel, panel_status(t), edits_, &widgets_);
    apply(actions, t);
    if (!controls_.apply(in, !imgui_.wants_mouse(), !imgui_.wants_keyboard(), t)) {
      return false;
    }
    for (int k = 0; k < kMaxTicksPerFrame && static_cast<double>(ticks_) * kTick <= t; ++k) {
      tick(static_cast<double>(ticks_) * kTick);
    }
    const Clock::time_point render_start = Clock::now();
    draw(window.height);
    history_.render_ms.push(static_cast<float>(ms_since(render_start)));
    imgui_.render();
    if (last && !o_.screenshot.empty()) {
      render::write_png(render::read_pixels(window_.target()), o_.screenshot);
    }
    window_.present();
    return true;
  }

  PanelStatus panel_status(double t) const {
    PanelStatus s;
    s.history = &history_;
    s.scripted_user = a_.user == nullptr;
    s.avatar_visible = remote_->remote.visible();
    s.local_objects = a_.a.target_map.objects;
    s.status = controls_.status();
    s.avatar = remote_->path.native();
    s.avatar_note = avatar_note_;
    s.seconds = t;
    s.ticks = ticks_;
    s.network = network_ ? &network_panel_ : nullptr;
    s.start_disabled = a_.peer_networks ? std::string_view() : kNoSessionWhenFixed;
    s.form_problem = form_problem_;
    return s;
  }

  void apply(const PanelActions& actions, double t) {
    if (actions.look_at_partner) {
      controls_.run(UserCommand::kLookAtPartner, kNoTarget, t);
    }
    if (actions.explain) {
      controls_.run(UserCommand::kExplain, kNoTarget, t);
    }
    if (actions.rest) {
      controls_.run(UserCommand::kRest, kNoTarget, t);
    }
    if (actions.point != kNoTarget) {
      controls_.run(UserCommand::kPoint, actions.point, t);
    }
    if (actions.touch != kNoTarget) {
      controls_.run(UserCommand::kTouch, actions.touch, t);
    }
    if (actions.reset_objects) {
      controls_.reset_objects();
    }
    if (actions.load_avatar) {
      const std::string text = edits_.avatar_path.data();
      load_avatar(text.empty() ? a_.b.avatar_path : fs::path(text));
    }
    if (actions.start_network && a_.peer_networks) {
      start_from_form();
    }
    if (actions.leave_network && network_) {
      leave_network();
    }
  }

  void load_avatar(const fs::path& glb) {
    try {
      remote_ = make_remote(glb);
      avatar_note_.clear();
    } catch (const Error& e) {
      // The previous avatar stays: a bad file is the person's to fix, not a reason to stop.
      avatar_note_ = std::string("Cannot load the avatar: ") + e.what();
      std::fprintf(stderr, "deixis sim: %s\n", avatar_note_.c_str());
    }
  }

  // One 30 Hz tick: the user's tracking at `tt`, their copy in A, their avatar in B.
  void tick(double tt) {
    if (a_.user) {
      a_.user->update(tt);
      user_frame_ = a_.user->sample(tt);
      user_deictic_ = a_.user->deictic(tt);
    } else {
      const auto& frames = a_.script->sequence.frames;
      const std::size_t i = std::min<std::size_t>(ticks_, frames.size() - 1);
      user_frame_ = frames[i];
      user_frame_.time = tt;
      user_deictic_ = a_.script->sequence.labels[i][1];
    }
    aim_at_people(user_frame_);
    user_copy_.solve(user_frame_);
    const LocalTargets room{&remote_map_, b_partner_head_};
    const Clock::time_point t0 = Clock::now();
    // The preview in B has one person, B's user: whoever the user looks at is them.
    TrackingFrame preview = user_frame_;
    for (TargetId* target : {&preview.head_target, &preview.hand_target}) {
      *target = is_person_target(*target) ? kPartnerTarget : *target;
    }
    remote_->remote.tick(&preview, room);
    const double took = ms_since(t0);
    history_.push_tick(remote_->remote.frame(), took);
    visible_ticks_ += remote_->remote.visible() ? 1 : 0;
    if (network_) {
      // The other person's avatar looks at the user where they stand in A.
      network_->tick(user_frame_,
                     LocalTargets{&a_.a.target_map, user_frame_.T_world_head.translation}, tt);
      network_panel_ = network_->panel();
    }
    ++ticks_;
  }

  // In a room the user's "other person" (where A's first avatar spot is, which the live user and
  // a script's target 0 look at) is whoever stands on that spot; people a script names by site
  // are whoever of that site is here (site/remote_people.h).
  void aim_at_people(TrackingFrame& frame) const {
    const bool running = network_ && network_->running();
    if (!running) {
      // No one else is here: the person a script names is the local preview's, B's user.
      for (TargetId* target : {&frame.head_target, &frame.hand_target}) {
        *target = is_script_person_target(*target) ? kPartnerTarget : *target;
      }
      return;
    }
    if (a_.a.virtual_user && !a_.a.virtual_user->people.empty()) {
      site::resolve_script_people(frame, a_.a.virtual_user->people, network_->people_here(),
                                  !network_->in_room());
    }
    if (!network_->in_room()) {
      return;
    }
    const PersonId first = network_->person_on_spot(0);
    for (TargetId* target : {&frame.head_target, &frame.hand_target}) {
      if (*target == kPartnerTarget && first != kNoPerson) {
        *target = person_target(first);
      }
    }
  }

  void draw(int window_height) {
    // Room A: the user's copy, and the other sites' people when networked.
    avatars_.clear();  // capacity: the user and every spot, reserved at construction
    lines_.clear();
    avatars_.push_back({local_meshes_.own(), user_copy_.T_world_model(), user_copy_.model_pose()});
    const TargetObject* user_target = a_.a.target_map.find(user_frame_.hand_target);
    if (user_target != nullptr && user_deictic_ > kRayShownAbove) {
      const EndEffectorPoses& e = user_copy_.targets().deictic;
      lines_.push_back(eye_ray(e.T_world_head.translation, e.index_tip, user_target->position));
    }
    if (network_) {
      for (const site::DrawnAvatar& other : network_->drawn_avatars()) {
        // What they wear here (their choice, the override, else A's avatar); not drawn when
        // more different avatars came than the cache holds.
        const std::optional<render::SkinnedMeshId> mesh = local_meshes_.get(other.mesh);
        if (mesh && avatars_.size() < avatars_.capacity()) {
          add_avatar(*other.avatar, *mesh, a_.a.target_map, other.opacity);
        }
      }
    }
    local_.draw(avatars_, lines_, window_height);

    // Room B: the user translated here.
    avatars_.clear();
    lines_.clear();
    if (remote_->remote.visible()) {
      add_avatar(remote_->remote, remote_->mesh, remote_map_);
    }
    remote_view_.draw(avatars_, lines_, window_height);
  }

  // A translated avatar, with its eye–fingertip ray toward its room's copy while it points.
  void add_avatar(const presence::RemoteAvatar& avatar, render::SkinnedMeshId mesh,
                  const TargetMap& room, float opacity = 1.0f) {
    avatars_.push_back({mesh, avatar.T_world_model(), avatar.model_pose(), opacity});
    const TargetObject* target = room.find(avatar.frame().hand_target);
    if (target != nullptr && avatar.frame().progression[1] > kRayShownAbove) {
      lines_.push_back(eye_ray(avatar.eye_midpoint(), avatar.index_fingertip(), target->position));
    }
  }

  int finish() {
    // What the session was at the end, before the bye ends it (its avatar still visible).
    const nlohmann::json network = network_json();
    if (network_) {
      for (const site::LivePerson& p : network_->people()) {
        network_people_.push_back({std::string(p.site), p.live, p.frames_played, p.visible_ticks,
                                   std::string(p.avatar), p.avatar_joints});
      }
      network_->close();
    }
    const auto quantiles = [](const Ring& r) {
      return nlohmann::json{{"p50", r.quantile(0.5f)}, {"p99", r.quantile(0.99f)}};
    };
    std::printf(
        "frames %llu, ticks %llu (avatar visible in %llu); translation + IK p50 %.3f ms, render "
        "p50 %.2f ms, frame p50 %.2f ms\n",
        static_cast<unsigned long long>(frames_), static_cast<unsigned long long>(ticks_),
        static_cast<unsigned long long>(visible_ticks_),
        static_cast<double>(history_.tick_ms.quantile(0.5f)),
        static_cast<double>(history_.render_ms.quantile(0.5f)),
        static_cast<double>(history_.frame_ms.quantile(0.5f)));
    const int code = print_network();
    if (o_.report.empty()) {
      return code;
    }
    nlohmann::json objects = nlohmann::json::array();
    for (const TargetObject& object : remote_map_.objects) {
      objects.push_back(
          {{"id", object.id},
           {"name", object.name},
           {"position", {object.position.x(), object.position.y(), object.position.z()}}});
    }
    const presence::RemoteAvatar& avatar = remote_->remote;
    const Vec3 eye = avatar.eye_midpoint();
    const Vec3 tip = avatar.index_fingertip();
    const render::RenderTarget window = window_.target();
    const SimLayout layout = sim_layout(window.width, window.height);
    const auto rect = [](const ViewRect& r) { return nlohmann::json{r.x, r.y, r.width, r.height}; };
    const nlohmann::json report = {
        {"frames", frames_},
        {"ticks", ticks_},
        {"visible_ticks", visible_ticks_},
        {"window", {window.width, window.height}},
        {"views", {{"local", rect(layout.local)}, {"remote", rect(layout.remote)}}},
        {"remote_objects", objects},
        {"user",
         {{"head_target", user_frame_.head_target}, {"hand_target", user_frame_.hand_target}}},
        {"avatar",
         {{"visible", avatar.visible()},
          {"hand_target", avatar.frame().hand_target},
          {"progression", avatar.frame().progression},
          {"eye", {eye.x(), eye.y(), eye.z()}},
          {"fingertip", {tip.x(), tip.y(), tip.z()}},
          {"glb", remote_->path.string()}}},
        {"status", controls_.status()},
        {"network", network},
        {"timings_ms",
         {{"translation_ik", quantiles(history_.tick_ms)},
          {"render", quantiles(history_.render_ms)},
          {"frame", quantiles(history_.frame_ms)}}}};
    std::ofstream out(o_.report);
    out << report.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "deixis sim: %s: cannot write the report\n", o_.report.c_str());
      return 1;
    }
    return code;
  }

  // The last session's summary; 1 when it failed (its error went to stderr then), else 0.
  int print_network() const {
    if (!network_) {
      return 0;
    }
    const site::LivePeerStats& n = network_->stats();
    std::printf(
        "network: site %s, tracking sent %llu, frames played %llu (%llu missed), their avatar "
        "visible in %llu ticks\n",
        n.peer_site.c_str(), static_cast<unsigned long long>(n.sent),
        static_cast<unsigned long long>(n.played), static_cast<unsigned long long>(n.missed),
        static_cast<unsigned long long>(n.visible_ticks));
    for (const PersonLine& p : network_people_) {
      std::printf(
          "person %s: frames played %llu, visible in %llu ticks, %s, wearing %s (%d joints)\n",
          p.site.c_str(), static_cast<unsigned long long>(p.frames_played),
          static_cast<unsigned long long>(p.visible_ticks), p.live ? "live" : "not live",
          p.avatar.c_str(), p.avatar_joints);
    }
    return network_->error().empty() ? 0 : 1;
  }

  nlohmann::json network_json() const {
    if (!network_) {
      return {{"role", "local"}};
    }
    const site::LivePeerStats& n = network_->stats();
    nlohmann::json people = nlohmann::json::array();
    for (const site::LivePerson& p : network_->people()) {
      people.push_back({{"site", p.site},
                        {"live", p.live},
                        {"frames_played", p.frames_played},
                        {"visible_ticks", p.visible_ticks},
                        {"avatar", {{"source", p.avatar}, {"joints", p.avatar_joints}}}});
    }
    return {{"role", network_panel_.role},
            {"room", network_panel_.room},
            {"port", network_panel_.port},
            {"peer_site", n.peer_site},
            {"sent", n.sent},
            {"played", n.played},
            {"missed", n.missed},
            {"visible_ticks", n.visible_ticks},
            {"visible", !network_->visible_avatars().empty()},
            {"people", people},
            {"state", network_panel_.state},
            {"error", network_->error()}};
  }

  const sim::SimOptions& o_;
  SimAssets& a_;
  render::WindowContext& window_;
  TargetMap remote_map_;  // B's objects as they stand now (dragged in place)
  RoomView local_;
  RoomView remote_view_;
  presence::CopiedAvatar user_copy_;
  // A's avatar (the user's copy, and whoever wears the default) and the avatars people chose,
  // each uploaded once.
  render::SkinnedMeshCache local_meshes_;
  SimControls controls_;
  ImGuiLayer imgui_;
  WindowInput window_input_;
  std::unique_ptr<RemoteSide> remote_;
  Vec3 b_partner_head_ = Vec3::Zero();
  PanelEdits edits_;
  std::string avatar_note_;
  SimHistory history_;
  std::optional<SimNetwork> network_;  // the last session (--host / --join, or the panel's)
  PanelNetwork network_panel_;         // its state, refreshed every tick
  std::string form_problem_;           // what the last Start found wrong in the form
  PanelWidgets widgets_;               // where the last frame drew the panel's widgets
  FindWidget find_widget_;             // widget_centre, for scripted clicks at a widget
  SimTime time_;                       // fixed steps when scripted, else (or once networked) wall
  std::vector<render::AvatarDraw> avatars_;  // this frame's avatars in one view
  std::vector<render::DebugLine> lines_;     // and their rays
  struct PersonLine {
    std::string site;
    bool live = false;
    std::uint64_t frames_played = 0, visible_ticks = 0;
    std::string avatar;
    int avatar_joints = 0;
  };
  std::vector<PersonLine> network_people_;  // who was there at the end (printed)
  TrackingFrame user_frame_;
  float user_deictic_ = 0.0f;
  std::uint64_t frames_ = 0;
  std::uint64_t ticks_ = 0;
  std::uint64_t visible_ticks_ = 0;
};

}  // namespace

int run_sim(const SimOptions& o) {
  std::optional<SimAssets> assets;
  try {
    assets.emplace(load_assets(o));
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis sim: %s\n", e.what());
    return 2;
  }
  try {
    render::WindowOptions window_options;
    window_options.width = o.width;
    window_options.height = o.height;
    window_options.title = "Deixis sim: " + assets->a.site + " and " + assets->b.site;
    window_options.vsync = !(o.fixed_step || !o.input.empty());
    render::WindowContext window(window_options);
    glfwSetInputMode(window.glfw_window(), GLFW_STICKY_MOUSE_BUTTONS, GLFW_TRUE);
    std::printf("window: %s\n", window.description().c_str());
    int code = 0;
    {
      Sim sim(o, *assets, window);
      code = sim.run();
    }
    return code;
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis sim: %s\n", e.what());
    return 1;
  }
}

}  // namespace deixis::sim
