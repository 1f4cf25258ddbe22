// `deixis sim` in a room of several people, as real processes on 127.0.0.1 (docs/sim.md, "In a
// room"): a `deixis relay`, two `deixis join --room` sites (B and C) and the simulator at site A
// with its scripted user, under a private Xvfb. Each joined site lists A as a person whose frames
// it played, and A's look at the person on its first spot (B) arrives as a look at B; the
// simulator lists B and C (report and stdout), and its last frame shows an avatar on each of A's
// two spots. Bad room flags exit 2 naming them. Every wait is bounded
// (deixis_child.h).

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "app/deixis_child.h"
#include "avatar/bcn_rig.h"  // tests/avatar
#include "core/target_map.h"
#include "sim/sim_window_fixture.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using sim::testing::display;
using sim::testing::read_json;

constexpr int kWidth = 640;  // the simulator's window
constexpr int kHeight = 480;

// The people a list names, by site.
std::map<std::string, json> by_site(const json& people) {
  std::map<std::string, json> out;
  if (people.is_array()) {
    for (const json& p : people) {
      out[p["site"].get<std::string>()] = p;
    }
  }
  return out;
}

class SimRoomTest : public ::testing::Test {
 protected:
  // The demo's site A, its camera to the left so that both avatar spots are in view and the
  // user's own copy (the same avatar) is on neither's line of sight.
  void SetUp() override {
    const fs::path assets = deixis::testing::source_dir() / "assets";
    json a = json::parse(std::ifstream(site("a.json")));
    a["target_map"] = (assets / "rooms/a.json").string();
    a["remote_avatar"]["avatar"] = (assets / "avatars/default.glb").string();
    a["camera"] = json::parse(
        R"({"position": [-2.0, 1.6, 0.5], "look_at": [0.4, 1.15, -1.6], "fov_degrees": 60})");
    std::ofstream(site_a()) << a.dump();
  }
  fs::path site_a() const { return dir_.path() / "a.json"; }

  std::vector<std::string> join(int port, const char* site_file, const char* out) const {
    return {"join",
            "--connect",
            "127.0.0.1:" + std::to_string(port),
            "--room",
            "meeting",
            "--site",
            site(site_file).string(),
            "--no-video",
            "--seconds",
            "22",
            "-o",
            (dir_.path() / out).string(),
            "--weights-dir",
            weights_dir(),
            "--wait",
            "20"};
  }
  std::vector<std::string> sim(int port) const {
    return {"sim",
            "--site-a",
            site_a().string(),
            "--connect",
            "127.0.0.1:" + std::to_string(port),
            "--room",
            "meeting",
            "--script",
            "--seconds",
            "12",
            "--weights-dir",
            weights_dir(),
            "--width",
            std::to_string(kWidth),
            "--height",
            std::to_string(kHeight),
            "--wait",
            "20",
            "--report",
            report().string(),
            "--screenshot",
            shot().string()};
  }
  fs::path report() const { return dir_.path() / "report.json"; }
  fs::path shot() const { return dir_.path() / "shot.png"; }

  // Pixels of the default avatar's shirt at the chest of whoever stands on site A's spot `k`.
  int shirt_on_spot(std::size_t k) const {
    return sim::testing::shirt_on_spot(site_a(), k, shot(), kWidth, kHeight);
  }

  deixis::testing::ScratchDir dir_;
};

TEST_F(SimRoomTest, TheSimulatorMeetsTwoSitesInARoomAndEachListsTheOthers) {
  const render::testing::XvfbServer& xvfb = display();
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  setenv("DEIXIS_PASSPHRASE", "one room, three sites", 1);
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  Deixis b(join(port, "b.json", "B"));
  Deixis c(join(port, "c.json", "C"));
  // The simulator starts once both are in (the relay logs "(2 now"), so that it meets them
  // early in its 12 s (its script looks at the other person at 0 s and 10 s); they stay 22 s,
  // beyond its end.
  ASSERT_TRUE(relay.wait_for_text("(2 now", 60.0)) << relay.out() << relay.err();
  Deixis a(sim(port) + std::vector<std::string>{"--avatar", deixis::testing::bcn_glb().string()});
  ASSERT_EQ(a.wait(), 0) << a.out() << a.err();
  EXPECT_EQ(b.wait(), 0) << b.err();
  EXPECT_EQ(c.wait(), 0) << c.err();
  unsetenv("DEIXIS_PASSPHRASE");
  relay.send_signal(SIGTERM);
  EXPECT_EQ(relay.wait(), 0) << relay.err();

  // The simulator: in the room, B and C each played into their own avatar and listed.
  const json n = read_json(report())["network"];
  std::printf("deixis sim in a room: %s\n", n.dump().c_str());
  EXPECT_EQ(n["role"], "room");
  EXPECT_EQ(n["room"], "meeting");
  EXPECT_EQ(n["state"], "in the room");
  EXPECT_EQ(n["error"], "");
  EXPECT_GT(n["sent"].get<int>(), 120);
  const std::map<std::string, json> people = by_site(n["people"]);
  ASSERT_EQ(people.size(), 2u) << n.dump(2);
  for (const char* other : {"B", "C"}) {
    ASSERT_TRUE(people.count(other)) << other << ": " << n.dump(2);
    EXPECT_GT(people.at(other)["frames_played"].get<int>(), 60) << other;
    EXPECT_GT(people.at(other)["visible_ticks"].get<int>(), 60) << other;
    EXPECT_TRUE(people.at(other)["live"].get<bool>()) << other;
    EXPECT_NE(a.out().find(std::string("person ") + other + ": frames played"), std::string::npos)
        << a.out();
  }
  // Each on their own spot of room A, both drawn in the last frame.
  EXPECT_GE(shirt_on_spot(0), 40) << "nobody drawn on A's first spot";
  EXPECT_GE(shirt_on_spot(1), 40) << "nobody drawn on A's second spot";

  // B and C each list the simulator's user (site A) as a person whose frames they played.
  for (const char* name : {"B", "C"}) {
    const json s = read_json(dir_.path() / name / "session.json");
    const std::map<std::string, json> met = by_site(s["people"]);
    ASSERT_TRUE(met.count("A")) << name << ": " << s.dump(2);
    EXPECT_GT(met.at("A")["frames_played"].get<int>(), 100) << name << ": " << met.at("A");
    EXPECT_GT(met.at("A")["visible_ticks"].get<int>(), 100) << name << ": " << met.at("A");
    std::printf("site %s saw the simulator's user: %s\n", name, met.at("A").dump().c_str());
    // The simulator's user chose the BCN rig (--avatar): they wear it there.
    EXPECT_EQ(met.at("A")["avatar"]["source"], "chosen") << name << ": " << met.at("A");
    EXPECT_EQ(met.at("A")["avatar"]["joints"].get<int>(), 54) << name << ": " << met.at("A");
    // People are targets: the script's "look at the other person" became whoever stands on A's
    // first spot (B, the first to arrive); B saw A look at B's own user, C saw A look at B's
    // avatar in room C, within a few degrees at least once (a look the run's end cuts short is
    // measured where it was then).
    double best = 180.0;
    for (const json& gaze : met.at("A")["gazes"]) {
      if (is_person_target(gaze["target"].get<TargetId>())) {
        best = std::min(best, gaze["error_deg"].get<double>());
      }
    }
    EXPECT_LT(best, 10.0) << name << ": " << met.at("A").dump();
  }
}

TEST_F(SimRoomTest, TheSimulatorEntersARoomFromItsPanel) {
  // No network flags: scripted input types the relay's address and the room's name into the
  // panel's form and presses Start, as a person would (the passphrase comes from the environment
  // into the form).
  const render::testing::XvfbServer& xvfb = display();
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  setenv("DEIXIS_PASSPHRASE", "one room, from the panel", 1);
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  Deixis b(join(port, "b.json", "B"));
  ASSERT_TRUE(relay.wait_for_text("(1 now", 60.0)) << relay.out() << relay.err();
  const auto event = [](double t, const char* type, const char* key, const std::string& value) {
    return json{{"t", t}, {"type", type}, {key, value}};
  };
  const json events = {event(0.3, "click", "widget", "Join"),
                       event(0.5, "click", "widget", "join address"),
                       event(0.7, "text", "text", "127.0.0.1:" + std::to_string(port)),
                       event(0.9, "click", "widget", "room"),
                       event(1.1, "text", "text", "meeting"),
                       event(1.3, "click", "widget", "Start")};
  const fs::path input = dir_.path() / "panel.json";
  std::ofstream(input) << json{{"format", "deixis-sim-input"}, {"version", 1}, {"events", events}};
  Deixis a({"sim", "--site-a", site_a().string(), "--input", input.string(), "--script",
            "--seconds", "9", "--weights-dir", weights_dir(), "--width", std::to_string(kWidth),
            "--height", std::to_string(kHeight), "--wait", "20", "--report", report().string()});
  ASSERT_EQ(a.wait(), 0) << a.out() << a.err();
  EXPECT_EQ(b.wait(), 0) << b.err();
  unsetenv("DEIXIS_PASSPHRASE");
  relay.send_signal(SIGTERM);
  EXPECT_EQ(relay.wait(), 0) << relay.err();

  const json n = read_json(report())["network"];
  std::printf("deixis sim, a room entered from the panel: %s\n", n.dump().c_str());
  EXPECT_EQ(n["role"], "room");
  EXPECT_EQ(n["room"], "meeting");
  EXPECT_EQ(n["port"].get<int>(), port);
  EXPECT_EQ(n["state"], "in the room");
  const std::map<std::string, json> people = by_site(n["people"]);
  ASSERT_TRUE(people.count("B")) << n.dump(2);
  EXPECT_GT(people.at("B")["frames_played"].get<int>(), 60);
  const std::map<std::string, json> met =
      by_site(read_json(dir_.path() / "B/session.json")["people"]);
  ASSERT_TRUE(met.count("A"));
  EXPECT_GT(met.at("A")["frames_played"].get<int>(), 60) << met.at("A");
}

TEST_F(SimRoomTest, BadRoomFlagsExitTwoNamingThem) {
  const std::vector<BadInput> cases = {
      {{"sim", "--room", "R"}, "--connect"},  // a room needs the relay
      {{"sim", "--connect", "127.0.0.1:7351"}, "--room"},
      {{"sim", "--host", "--room", "R"}, "--host"},
      {{"sim", "--join", "127.0.0.1:7350", "--connect", "127.0.0.1:7351", "--room", "R"}, "--join"},
      {{"sim", "--connect", "127.0.0.1:7351", "--room", ""}, "--room"},
      {{"sim", "--open", "--frames", "1"}, "--open"},
      // An open room through a relay beyond this machine needs --open, as for join.
      {{"sim", "--connect", "192.0.2.1:7351", "--room", "R"}, "--open"},
  };
  unsetenv("DEIXIS_PASSPHRASE");
  expect_refused(cases);
}

}  // namespace
}  // namespace deixis::app
