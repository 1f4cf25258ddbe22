// A site driven by a BVH recording over real processes (docs/bvh.md#driving-a-site): `deixis
// host` whose virtual user is Debian's CMU recording 01_01.bvh (subject 01, a real person) and
// `deixis join` with the demo's site B, over ENet on 127.0.0.1. The host says what it plays; the
// joiner plays the recorded person's frames into their avatar, which is visible; the host plays
// B's scripted user as always.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
const fs::path kCmu = "/usr/share/assimp/models/BVH/01_01.bvh";

json read_json(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return in ? json::parse(in) : json();
}

// The demo's site A with its virtual user replaced by `virtual_user`, written into `dir`.
fs::path recorded_site_a(const fs::path& dir, const json& virtual_user) {
  json a = read_json(site("a.json"));
  const fs::path sites = site("a.json").parent_path();
  a["target_map"] = (sites / a["target_map"].get<std::string>()).lexically_normal().string();
  a["remote_avatar"]["avatar"] =
      (sites / a["remote_avatar"]["avatar"].get<std::string>()).lexically_normal().string();
  a["virtual_user"] = virtual_user;
  const fs::path path = dir / "a-recorded.json";
  std::ofstream(path) << a.dump(2);
  return path;
}

std::vector<std::string> flags(const fs::path& site_file, const fs::path& out) {
  return {"--site",      site_file.string(), "--out", out.string(), "--weights-dir",
          weights_dir(), "--seconds",        "6",     "--wait",     "30",
          "--no-video"};
}

TEST(RecordedSite, AHostPlayingARecordingIsFollowedByTheJoinersAvatar) {
  if (!fs::exists(kCmu)) {
    GTEST_SKIP() << "no " << kCmu << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  deixis::testing::ScratchDir dir;
  const fs::path a = recorded_site_a(dir.path(), {{"bvh", kCmu.string()}, {"from", 2.0}});
  Deixis host(std::vector<std::string>{"host", "--port", "0", "--bind", "127.0.0.1"} +
              flags(a, dir.path() / "A"));
  const int port = host.port();
  ASSERT_GT(port, 0) << host.err();
  Deixis join(std::vector<std::string>{"join", "--connect", "127.0.0.1:" + std::to_string(port)} +
              flags(site("b.json"), dir.path() / "B"));
  ASSERT_EQ(join.wait(), 0) << join.err();
  ASSERT_EQ(host.wait(), 0) << host.err();
  // The host names the recording, its unit and the body its hello sent.
  // From 2 s on: frames 240 to 2751; 6 s at 30 Hz, both ends.
  const std::string said = "virtual user: " + kCmu.string() +
                           ", 2512 frames at 120.0 Hz (unit cmu), looping, 181 samples at 30 Hz; "
                           "body height 1.";
  EXPECT_NE(host.err().find(said), std::string::npos) << host.err();

  const json b = read_json(dir.path() / "B/session.json");
  EXPECT_EQ(b["peer_site"], "A");
  EXPECT_GT(b["network"]["frames_played"].get<int>(), 100) << b.dump(2);
  EXPECT_EQ(b["network"]["rejected"].get<int>(), 0);
  EXPECT_GT(b["avatar_visible_ticks"].get<int>(), 100) << b.dump(2);
  const json h = read_json(dir.path() / "A/session.json");
  EXPECT_EQ(h["peer_site"], "B");
  EXPECT_GT(h["network"]["frames_played"].get<int>(), 100);
}

TEST(RecordedSite, ABadRecordingStopsTheHostBeforeItListens) {
  deixis::testing::ScratchDir dir;
  std::ofstream(dir.path() / "cut.bvh")
      << "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n}\n"
         "MOTION\nFrames: 3\nFrame Time: 0.01\n0 1 2\n";
  const fs::path a = recorded_site_a(dir.path(), {{"bvh", "cut.bvh"}});
  Deixis host(std::vector<std::string>{"host", "--port", "0", "--bind", "127.0.0.1"} +
              flags(a, dir.path() / "A"));
  EXPECT_EQ(host.wait(), 2);
  const std::string said = a.string() + ": virtual_user.bvh: " + (dir.path() / "cut.bvh").string();
  EXPECT_NE(host.err().find(said + ":"), std::string::npos) << host.err();
  EXPECT_EQ(host.out().find("port "), std::string::npos) << "never listened";
}

}  // namespace
}  // namespace deixis::app
