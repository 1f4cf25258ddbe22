// `deixis sim --script` with a recorded user (docs/bvh.md#driving-a-site), the built command
// under a private Xvfb: site A's user is the boxer of Debian's Boxing_Toes.bvh
// (assets/sites/a-recorded.json), who designates nothing, and the avatar in room B follows.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "app/deixis_child.h"
#include "render/xvfb_server.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;

TEST(SimRecorded, ARecordedUserRunsHandsFree) {
  const render::testing::XvfbServer xvfb;
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  if (!fs::exists("/usr/share/assimp/models/BVH/Boxing_Toes.bvh")) {
    GTEST_SKIP() << "no Boxing_Toes.bvh (Debian's assimp-testmodels; tools/install-deps)";
  }
  deixis::testing::ScratchDir dir;
  const fs::path report_file = dir.path() / "report.json";
  Deixis sim({"sim", "--script", "--fixed-step", "--frames", "60", "--site-a",
              site("a-recorded.json").string(), "--weights-dir", weights_dir(), "--width", "640",
              "--height", "480", "--report", report_file.string()});
  ASSERT_EQ(sim.wait(), 0) << sim.err();
  EXPECT_NE(sim.out().find("frames 60, ticks 60"), std::string::npos) << sim.out();
  std::ifstream in(report_file);
  ASSERT_TRUE(in.good()) << report_file;
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["status"], "The user follows the site's script");
  EXPECT_GE(report["visible_ticks"].get<int>(), 59);
  EXPECT_EQ(report["user"]["hand_target"].get<int>(), -1);
}

}  // namespace
}  // namespace deixis::app
