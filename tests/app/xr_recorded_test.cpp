// `deixis xr` without a network, whose remote person is a recording (docs/bvh.md#driving-a-site):
// the built command on the project's OpenXR test runtime, headless; --remote-site is
// assets/sites/a-recorded.json (the boxer of Debian's Boxing_Toes.bvh), played locally and
// translated into room B at 30 Hz, the avatar visible on every tick.

#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <string>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;

TEST(XrRecorded, ARecordedRemotePersonIsTranslatedWithoutANetwork) {
  if (!fs::exists("/usr/share/assimp/models/BVH/Boxing_Toes.bvh")) {
    GTEST_SKIP() << "no Boxing_Toes.bvh (Debian's assimp-testmodels; tools/install-deps)";
  }
  setenv("XR_RUNTIME_JSON", DEIXIS_XR_RUNTIME_JSON, 1);
  unsetenv("XR_ENABLE_API_LAYERS");
  unsetenv("DEIXIS_XR_SCRIPT");
  Deixis xr({"xr", "--headless", "--seconds", "3", "--site", site("b.json").string(),
             "--remote-site", site("a-recorded.json").string(), "--weights-dir", weights_dir()});
  ASSERT_EQ(xr.wait(), 0) << xr.err();
  std::smatch m;
  const std::string out = xr.out();
  ASSERT_TRUE(std::regex_search(
      out, m, std::regex(R"(translation ticks (\d+) \(avatar visible in (\d+)\))")))
      << out;
  EXPECT_GE(std::stoi(m[1]), 80) << out;  // 3 s at 30 Hz
  EXPECT_EQ(m[1], m[2]) << out;
}

}  // namespace
}  // namespace deixis::app
