#pragma once
// What the LivePeer tests share: a demo site with its virtual user's performance as the user's
// 30 Hz tracking, and a relay serving on a thread of its own.

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "net/enet_link.h"
#include "net/relay_server.h"
#include "presence/remote_avatar.h"
#include "site/site_config.h"
#include "site/site_session.h"
#include "test_support.h"

namespace deixis::site::fixtures {

// One site: its configuration, avatar solver and its user's 30 Hz tracking.
struct Site {
  SiteConfig config;
  ik::AvatarSolver solver;
  BodyCalibration body;
  std::vector<TrackingFrame> frames;

  explicit Site(const std::string& name)
      : config(read_site_config(deixis::testing::source_dir() / "assets/sites" / name)),
        solver(ik::AvatarSolver::build(avatar::load_avatar(config.avatar_path).rig)) {
    const Pose partner = presence::avatar_origin(solver, config.remote_avatar.T_world_floor());
    const capture::VirtualUserScene scene{config.user.T_world_floor(), config.target_map.objects,
                                          partner.translation};
    const VirtualUser& user = *config.virtual_user;
    capture::ScriptPerformance performed = capture::perform_script(
        capture::find_subject(user.subject), user.script, scene, user.seed, 30.0);
    body = performed.sequence.calibration;
    frames = std::move(performed.sequence.frames);
  }
  const TrackingFrame& frame(std::size_t tick) const { return frames[tick % frames.size()]; }
};

// A relay serving on a thread of its own until destroyed.
class RelayThread {
 public:
  RelayThread()
      : link_(net::EnetLink::host("127.0.0.1", 0, net::HostLimits{64, 64})),
        relay_(*link_, net::RelayServerConfig{}),
        thread_([this] {
          const SiteClock clock;
          while (!stop_) {
            relay_.service(clock.now(), 1);
          }
        }) {}
  ~RelayThread() {
    stop_ = true;
    thread_.join();
  }
  std::uint16_t port() const { return link_->port(); }

 private:
  std::unique_ptr<net::EnetLink> link_;
  net::RelayServer relay_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace deixis::site::fixtures
