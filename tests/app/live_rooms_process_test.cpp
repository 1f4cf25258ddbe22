// `deixis eval --live-rooms` as a user runs it: a generated room pair run as `deixis host` and
// `deixis join` (real processes on loopback, started by the command itself), the completions
// both sites observed pooled into live_rooms.md, .json and .png, under rules of its own (--rules);
// bad flags exit 2 naming them.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

TEST(LiveRoomsProcess, OnePairIsRunAndItsCompletionsReported) {
  deixis::testing::ScratchDir dir;
  const fs::path out = dir.path() / "eval";
  // Rules of its own (--rules): the pointing targets 1.0–1.6 m high.
  const fs::path rules = dir.path() / "rules.json";
  std::ofstream(rules) << R"({"format": "deixis-room-rules", "version": 1,
                             "point_height": [1.0, 1.6]})";
  Deixis eval({"eval", "--live-rooms", "1", "--seed", "29", "--subjects", "172,180", "--rules",
               rules.string(), "--out", out.string()});
  ASSERT_EQ(eval.wait(), 0) << eval.out() << eval.err();
  std::printf("%s", eval.out().c_str());
  for (const char* file : {"live_rooms.md", "live_rooms.json", "live_rooms.png"}) {
    ASSERT_TRUE(fs::exists(out / file)) << file;
    EXPECT_GT(fs::file_size(out / file), 200u) << file;
  }
  // The pair's generated sites and both sites' reports are kept beside the summary.
  for (const char* file :
       {"a.json", "b.json", "room-a.json", "room-b.json", "A/session.json", "B/session.json"}) {
    EXPECT_TRUE(fs::exists(out / "live_rooms/pair-000" / file)) << file;
  }
  const json r = json::parse(std::ifstream(out / "live_rooms.json"));
  EXPECT_EQ(r["pairs"], 1);
  EXPECT_EQ(r["rules"]["point_height"], json::parse("[1.0, 1.6]")) << r["rules"].dump();
  EXPECT_EQ(r["rules"]["point_distance"], json::parse("[1.2, 3.4]")) << "a default kept";
  int pointing_targets = 0;
  for (const char* room : {"room-a.json", "room-b.json"}) {
    const json map = json::parse(std::ifstream(out / "live_rooms/pair-000" / room));
    for (const json& o : map["objects"]) {
      if (o["id"].get<int>() <= 3) {  // the pointing targets
        ++pointing_targets;
        EXPECT_GE(o["position"][1].get<double>(), 1.0 - 1e-3) << room << o.dump();
        EXPECT_LE(o["position"][1].get<double>(), 1.6 + 1e-3) << room << o.dump();
      }
    }
  }
  EXPECT_EQ(pointing_targets, 6);
  // Each user points at three targets and touches one; each site observes the other's.
  int points = 0, touches = 0;
  for (const json& c : r["completions"]) {
    SCOPED_TRACE(c.dump());
    if (c["kind"] == "point") {
      ++points;
      for (const char* system : {"avatar", "copy"}) {
        for (const char* angle : {"he_deg", "ve_deg"}) {
          ASSERT_TRUE(c[system][angle].is_number());
          EXPECT_GE(c[system][angle].get<double>(), 0.0);
          EXPECT_LE(c[system][angle].get<double>(), 180.0);
        }
      }
      EXPECT_GE(c["distance_m"].get<double>(), 0.0);
      EXPECT_LE(std::abs(c["azimuth_deg"].get<double>()), 180.0);
    } else {
      ++touches;
      ASSERT_TRUE(c["avatar"]["touch_cm"].is_number());
      EXPECT_GE(c["avatar"]["touch_cm"].get<double>(), 0.0);
    }
  }
  EXPECT_GE(points, 4) << r.dump(2);
  EXPECT_EQ(r["touches_performed"], 2);
  EXPECT_EQ(r["all"]["deixis"]["he_deg"]["count"], points);
  // Deixis beats copying the pose in rooms that differ (the method's point; the figures are the
  // harness's to report, this only asks that translation happened).
  EXPECT_LT(r["all"]["deixis"]["he_deg"]["mean"].get<double>(),
            r["all"]["copy_paste"]["he_deg"]["mean"].get<double>());
  std::ostringstream md;
  md << std::ifstream(out / "live_rooms.md").rdbuf();
  EXPECT_NE(md.str().find("per target geometry"), std::string::npos) << md.str();
}

TEST(LiveRoomsProcess, BadFlagsExit2NamingThem) {
  deixis::testing::ScratchDir dir;
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"eval", "--live-rooms", "0"}, "--live-rooms"},
      {{"eval", "--seed", "3"}, "--live-rooms"},  // a seed means nothing without rooms
      {{"eval", "--live-rooms", "1", "--subjects", "999", "--out", dir.path().string()}, "999"},
      {{"eval", "--live-rooms", "1", "--pair-timeout", "1"}, "--pair-timeout"},
      {{"eval", "--live-rooms", "1", "--rules", (dir.path() / "none.json").string()}, "--rules"},
      {{"eval", "--live-rooms", "1", "--weights-dir", (dir.path() / "none").string()},
       "--weights-dir"},
      {{"eval", "--weights-dir", dir.path().string()}, "--live-rooms"},
      {{"eval", "--live-rooms", "1", "--rules", (dir.path() / "rules.json").string(), "--out",
        dir.path().string()},
       "point_height"},
  };
  std::ofstream(dir.path() / "rules.json")
      << R"({"format": "deixis-room-rules", "version": 1, "point_height": [2.0, 1.0]})";
  for (const auto& [args, named] : cases) {
    Deixis eval(args);
    EXPECT_EQ(eval.wait(), 2) << eval.err();
    EXPECT_NE(eval.err().find(named), std::string::npos) << eval.err();
  }
  EXPECT_FALSE(fs::exists(dir.path() / "live_rooms.json"));
}

}  // namespace
}  // namespace deixis::app
