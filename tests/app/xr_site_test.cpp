// `deixis xr` as a networked site, for real: a headset user in room A (site A's scripted person
// wearing the OpenXR test runtime's headset, paced to the wall clock) joins `deixis host` at
// site B over ENet on 127.0.0.1. The xr site calibrates the user from the first tracked frame,
// selects what they look and point at from the tracking and streams it; site B translates the
// headset user into room B, where the objects stand elsewhere, and measures the avatar at the
// person's completion states against copying the pose (eval/deictic_observer.h). Also: a wrong
// passphrase ends the xr session with the refusal, and bad flags exit 2 naming them.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/deixis_child.h"
#include "app/scripted_person.h"
#include "site/site_config.h"
#include "test_support.h"
#include "tests/xr/runtime_script.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// Site A with a short script for the headset user: look at the other person, point at object 1,
// rest, touch object 4, rest.
std::string short_site_a() {
  const fs::path assets = deixis::testing::source_dir() / "assets";
  json a = json::parse(std::ifstream(site("a.json")));
  a["target_map"] = (assets / "rooms/a.json").string();
  a["remote_avatar"]["avatar"] = (assets / "avatars/default.glb").string();
  a["virtual_user"]["script"] = json::parse(R"([
      {"action": "look_at", "target": 0, "seconds": 1.0},
      {"action": "point", "target": 1, "seconds": 1.5},
      {"action": "rest", "seconds": 0.5},
      {"action": "touch", "target": 4, "seconds": 1.5},
      {"action": "rest", "seconds": 1.0}])");
  return a.dump();
}

class XrSite : public ::testing::Test {
 protected:
  void SetUp() override {
    site_a_ = dir_.path() / "a.json";
    std::ofstream(site_a_) << short_site_a();
    const std::vector<TrackingFrame> person = performed_virtual_user(site_a_);
    seconds_ = static_cast<double>(person.size()) / 30.0;
    std::ofstream(dir_.path() / "script.json") << xr::runtime_script(person, /*realtime=*/true);
    setenv("XR_RUNTIME_JSON", DEIXIS_XR_RUNTIME_JSON, 1);
    setenv("DEIXIS_XR_SCRIPT", (dir_.path() / "script.json").c_str(), 1);
    unsetenv("XR_ENABLE_API_LAYERS");
  }

  std::vector<std::string> xr_flags(int port) const {
    return {"xr",
            "--headless",
            "--site",
            site("a.json").string(),
            "--join",
            "127.0.0.1:" + std::to_string(port),
            "--weights-dir",
            weights_dir(),
            "--wait",
            "10"};
  }
  std::vector<std::string> host_flags(const std::string& seconds) const {
    return {"host",        "--site",     site("b.json").string(),
            "--port",      "0",          "--bind",
            "127.0.0.1",   "--no-video", "--weights-dir",
            weights_dir(), "--out",      (dir_.path() / "B").string(),
            "--seconds",   seconds};
  }

  deixis::testing::ScratchDir dir_;
  fs::path site_a_;
  double seconds_ = 0.0;  // the headset user's performance
};

json read_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return in ? json::parse(in) : json();
}

TEST_F(XrSite, TheHeadsetUsersAvatarPointsAndTouchesAtRoomBsCopies) {
  // The host streams until after the headset user is done.
  Deixis host(host_flags(std::to_string(static_cast<int>(seconds_) + 3).c_str()));
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  Deixis headset(xr_flags(port));
  ASSERT_EQ(headset.wait(), 0) << headset.out() << headset.err();
  ASSERT_EQ(host.wait(), 0) << host.err();

  // The xr site: calibrated, streamed with B, and showed B's person in room A.
  EXPECT_NE(headset.out().find("calibrated: stature"), std::string::npos) << headset.out();
  EXPECT_NE(headset.out().find("network: site B"), std::string::npos) << headset.out();

  // Site B translated the headset user, who pointed at object 1 and touched object 4.
  const json s = read_json(dir_.path() / "B/session.json");
  EXPECT_EQ(s["peer_site"], "A");
  EXPECT_GT(s["network"]["frames_played"].get<int>(), 200);
  EXPECT_EQ(s["network"]["rejected"].get<int>(), 0);
  EXPECT_GT(s["avatar_visible_ticks"].get<int>(), 200);
  const json& pointing = s["pointing"];
  const json& touching = s["touching"];
  std::printf("site B saw the headset user: pointing %s\n  touching %s\n", pointing.dump().c_str(),
              touching.dump().c_str());
  ASSERT_GE(pointing["count"].get<int>(), 1) << s.dump(2);
  // As for two scripted sites (deixis_process_test): the issue-6 accuracy itself (≤ 5°) is
  // checked on many held-out sequences by end_to_end_test and, through the headset path, by
  // xr_point_at_test; here one hold in the demo's rooms, as the observer at site B sees it.
  EXPECT_LT(pointing["avatar_horizontal_deg"].get<double>(), 10.0) << s.dump(2);
  EXPECT_LT(pointing["avatar_vertical_deg"].get<double>(), 10.0) << s.dump(2);
  EXPECT_GT(
      pointing["copy_horizontal_deg"].get<double>() + pointing["copy_vertical_deg"].get<double>(),
      3 * (pointing["avatar_horizontal_deg"].get<double>() +
           pointing["avatar_vertical_deg"].get<double>()))
      << s.dump(2);
  ASSERT_GE(touching["count"].get<int>(), 1) << s.dump(2);
  EXPECT_LT(touching["avatar_touch_cm"].get<double>(), 3.0) << s.dump(2);
  EXPECT_GT(touching["copy_touch_cm"].get<double>(), 3 * touching["avatar_touch_cm"].get<double>())
      << s.dump(2);
}

TEST_F(XrSite, AWrongPassphraseEndsTheSessionWithTheRefusal) {
  Deixis host(host_flags("4") +
              std::vector<std::string>{"--passphrase", "blue whale", "--wait", "4"});
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  Deixis headset(xr_flags(port) + std::vector<std::string>{"--passphrase", "green whale"});
  EXPECT_EQ(headset.wait(), 1) << headset.out();
  EXPECT_NE(headset.err().find("refused this site: wrong passphrase"), std::string::npos)
      << headset.err();
  EXPECT_EQ(host.wait(), 1);
}

TEST_F(XrSite, BadFlagsExitTwoNamingThem) {
  const std::vector<BadInput> cases = {
      {{"xr", "--join", "localhost"}, "--join"},
      {{"xr", "--join", "127.0.0.1:99999"}, "--join"},
      {{"xr", "--port", "7000"}, "--port"},  // only with --host
      {{"xr", "--host", "--join", "127.0.0.1:7000"}, "--join"},
      {{"xr", "--hand", "both"}, "--hand"},
      {{"xr", "--height", "3"}, "--height"},
  };
  expect_refused(cases);
}

}  // namespace
}  // namespace deixis::app
