// `deixis xr` in a room of several people, for real (docs/xr.md, "In a room"): a `deixis relay`
// and `deixis join --room` at site B on 127.0.0.1, and the headset user at site A (site A's
// scripted person wearing the OpenXR test runtime's headset, paced to the wall clock) entering
// the same room with `deixis xr --connect --room`. Site B lists A as a person whose frames it
// played, and A's gaze at B's avatar in room A arrives as a gaze at B's own user; the headset's
// site lists B as a person whose frames it played, wearing the avatar B chose (the BCN test rig:
// the headset's site fetched it over the room and draws B in it). Bad room flags exit 2 naming
// them.

#include <gtest/gtest.h>
#include <signal.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/deixis_child.h"
#include "avatar/avatar_loader.h"
#include "avatar/bcn_rig.h"  // tests/avatar
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/target_map.h"
#include "presence/remote_avatar.h"
#include "site/site_config.h"
#include "test_support.h"
#include "tests/xr/runtime_script.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// The headset user's 8 s: looks at whoever is on the first spot, points, touches, points again.
constexpr const char* kHeadsetScript = R"([
    {"action": "look_at", "target": 0, "seconds": 1.0},
    {"action": "point", "target": 1, "seconds": 1.5},
    {"action": "rest", "seconds": 0.5},
    {"action": "touch", "target": 4, "seconds": 1.5},
    {"action": "rest", "seconds": 1.0},
    {"action": "point", "target": 1, "seconds": 1.5},
    {"action": "rest", "seconds": 1.0}])";

class XrRoom : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path assets = deixis::testing::source_dir() / "assets";
    json a = json::parse(std::ifstream(site("a.json")));
    a["target_map"] = (assets / "rooms/a.json").string();
    a["remote_avatar"]["avatar"] = (assets / "avatars/default.glb").string();
    a["virtual_user"]["script"] = json::parse(kHeadsetScript);
    site_a_ = dir_.path() / "a.json";
    std::ofstream(site_a_) << a.dump();

    // Site A's person performed in room A, worn as the test runtime's headset.
    const site::SiteConfig config = site::read_site_config(site_a_);
    const ik::AvatarSolver solver =
        ik::AvatarSolver::build(avatar::load_avatar(config.avatar_path).rig);
    const Pose partner = presence::avatar_origin(solver, config.remote_avatar.T_world_floor());
    const capture::VirtualUserScene scene{config.user.T_world_floor(), config.target_map.objects,
                                          partner.translation};
    const site::VirtualUser& user = *config.virtual_user;
    const std::vector<TrackingFrame> person =
        capture::perform_script(capture::find_subject(user.subject), user.script, scene, user.seed)
            .sequence.frames;
    seconds_ = static_cast<double>(person.size()) / 30.0;
    std::ofstream(dir_.path() / "script.json") << xr::runtime_script(person, /*realtime=*/true);
    setenv("XR_RUNTIME_JSON", DEIXIS_XR_RUNTIME_JSON, 1);
    setenv("DEIXIS_XR_SCRIPT", (dir_.path() / "script.json").c_str(), 1);
    unsetenv("XR_ENABLE_API_LAYERS");
  }
  void TearDown() override { unsetenv("DEIXIS_PASSPHRASE"); }

  deixis::testing::ScratchDir dir_;
  fs::path site_a_;
  double seconds_ = 0.0;  // the headset user's performance
};

TEST_F(XrRoom, TheHeadsetUserAndAJoinedSiteEachListTheOtherAsAPerson) {
  setenv("DEIXIS_PASSPHRASE", "a headset in the room", 1);
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  const std::string relay_at = "127.0.0.1:" + std::to_string(port);
  // Site B stays until well after the headset user is done.
  Deixis b({"join", "--connect", relay_at, "--room", "meeting", "--site", site("b.json").string(),
            "--no-video", "--seconds", std::to_string(static_cast<int>(seconds_) + 8), "-o",
            (dir_.path() / "B").string(), "--weights-dir", weights_dir(), "--wait", "20",
            "--avatar", deixis::testing::bcn_glb().string()});
  ASSERT_TRUE(relay.wait_for_text("(1 now", 60.0)) << relay.out() << relay.err();
  // The headset user chose the BCN rig too: B shows them wearing it.
  Deixis headset({"xr", "--headless", "--site", site_a_.string(), "--connect", relay_at, "--room",
                  "meeting", "--weights-dir", weights_dir(), "--wait", "20", "--avatar",
                  deixis::testing::bcn_glb().string()});
  ASSERT_EQ(headset.wait(), 0) << headset.out() << headset.err();
  ASSERT_EQ(b.wait(), 0) << b.err();
  relay.send_signal(SIGTERM);
  EXPECT_EQ(relay.wait(), 0) << relay.err();

  // The headset's site: calibrated, in the room with B, whose person it played.
  std::printf("%s", headset.out().c_str());
  EXPECT_NE(headset.out().find("calibrated: stature"), std::string::npos) << headset.out();
  EXPECT_NE(headset.out().find("network: site B"), std::string::npos) << headset.out();
  const std::size_t at = headset.out().find("person B: frames played ");
  ASSERT_NE(at, std::string::npos) << headset.out();
  const int played_b = std::atoi(headset.out().c_str() + at + 24);
  EXPECT_GT(played_b, 60) << headset.out();
  // B wears the avatar B chose (54 joints; the site's default has another count).
  EXPECT_NE(headset.out().find("wearing chosen (54 joints)", at), std::string::npos)
      << headset.out();

  // Site B: the headset user (site A) is a person of the room whose frames it played.
  std::ifstream in(dir_.path() / "B/session.json");
  ASSERT_TRUE(in.good());
  const json s = json::parse(in);
  const json* a = nullptr;
  for (const json& p : s["people"]) {
    a = p["site"] == "A" ? &p : a;
  }
  ASSERT_NE(a, nullptr) << s.dump(2);
  std::printf("site B saw the headset user: %s\n", a->dump().c_str());
  EXPECT_GT((*a)["frames_played"].get<int>(), 100) << a->dump();
  EXPECT_GT((*a)["visible_ticks"].get<int>(), 100) << a->dump();
  EXPECT_EQ((*a)["avatar"]["source"], "chosen") << a->dump();
  EXPECT_EQ((*a)["avatar"]["joints"].get<int>(), 54) << a->dump();

  // People are targets: when the headset user looked at B's avatar in room A, the selection
  // designated B (person_target, not an object), and A's avatar in room B looked at B's user.
  int at_people = 0;
  for (const json& gaze : (*a)["gazes"]) {
    if (is_person_target(gaze["target"].get<TargetId>())) {
      ++at_people;
      EXPECT_LT(gaze["error_deg"].get<double>(), 10.0) << gaze;
    }
  }
  EXPECT_GE(at_people, 1) << a->dump();
}

TEST_F(XrRoom, BadRoomFlagsExitTwoNamingThem) {
  const std::vector<BadInput> cases = {
      {{"xr", "--headless", "--room", "R"}, "--connect"},
      {{"xr", "--headless", "--connect", "127.0.0.1:7351"}, "--room"},
      {{"xr", "--headless", "--host", "--room", "R"}, "--host"},
      {{"xr", "--headless", "--join", "127.0.0.1:7350", "--connect", "127.0.0.1:7351", "--room",
        "R"},
       "--join"},
      {{"xr", "--headless", "--open"}, "--open"},
      {{"xr", "--headless", "--connect", "192.0.2.1:7351", "--room", "R"}, "--open"},
  };
  unsetenv("DEIXIS_PASSPHRASE");
  expect_refused(cases);
}

}  // namespace
}  // namespace deixis::app
