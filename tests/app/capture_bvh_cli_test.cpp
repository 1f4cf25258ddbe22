// `deixis capture bvh` as a user runs it (the built command, a real process): a Debian recording's
// tracking as CSV whose rows parse, finite and valid, for the frames asked; bad flags and bad files
// exit non-zero with a message naming them.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;
const fs::path kCmu = "/usr/share/assimp/models/BVH/01_01.bvh";

std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::istringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) {
      cells.push_back(cell);
    }
    rows.push_back(cells);
  }
  return rows;
}

TEST(CaptureBvhCli, ARecordingBecomesTrackingCsv) {
  if (!fs::exists(kCmu)) {
    GTEST_SKIP() << "no " << kCmu << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  deixis::testing::ScratchDir dir;
  const fs::path out = dir.path() / "t.csv";
  Deixis run(
      {"capture", "bvh", kCmu.string(), "--csv", out.string(), "--from", "100", "--to", "400"});
  ASSERT_EQ(run.wait(), 0) << run.err();
  EXPECT_NE(run.err().find("unit cmu"), std::string::npos) << run.err();
  const auto rows = read_csv(out);
  ASSERT_EQ(rows.size(), 301u);
  ASSERT_EQ(rows[0].size(), 33u);
  EXPECT_EQ(rows[0][3], "head_x");
  EXPECT_EQ(rows[1][0], "100");
  for (std::size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), rows[0].size()) << r;
    EXPECT_EQ(rows[r][2], "15") << r;  // every part valid
    for (const std::string& cell : rows[r]) {
      const double v = std::stod(cell);
      EXPECT_TRUE(std::isfinite(v)) << cell;
    }
    EXPECT_GT(std::stod(rows[r][4]), 1.0) << "H is above 1 m standing";
  }
}

// --rate 30 through the player: 3 s of the 120 Hz recording give 91 rows whose times step by
// 1/30 s from --from's time, and where a sample falls on a recorded frame (every fourth) it is
// that frame's row of the run without --rate (within 1e-4). 45 Hz falls between frames: its rows
// are finite and step by 1/45 s.
TEST(CaptureBvhCli, RateResamplesThroughThePlayer) {
  if (!fs::exists(kCmu)) {
    GTEST_SKIP() << "no " << kCmu << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  deixis::testing::ScratchDir dir;
  const fs::path own = dir.path() / "own.csv";
  const fs::path at30 = dir.path() / "30.csv";
  const fs::path at45 = dir.path() / "45.csv";
  const std::vector<std::string> range = {"--from", "120", "--to", "481"};
  Deixis a(std::vector<std::string>{"capture", "bvh", kCmu.string(), "--csv", own.string()} +
           range);
  ASSERT_EQ(a.wait(), 0) << a.err();
  Deixis b(std::vector<std::string>{"capture", "bvh", kCmu.string(), "--csv", at30.string(),
                                    "--rate", "30"} +
           range);
  ASSERT_EQ(b.wait(), 0) << b.err();
  EXPECT_NE(b.err().find("resampled at 30 Hz"), std::string::npos) << b.err();
  Deixis c(std::vector<std::string>{"capture", "bvh", kCmu.string(), "--csv", at45.string(),
                                    "--rate", "45"} +
           range);
  ASSERT_EQ(c.wait(), 0) << c.err();
  const auto rows = read_csv(own);
  const auto rows30 = read_csv(at30);
  const auto rows45 = read_csv(at45);
  ASSERT_EQ(rows.size(), 362u);
  ASSERT_EQ(rows30.size(), 92u);
  ASSERT_EQ(rows45.size(), 137u);  // 3 s x 45 + 1 samples and the header
  EXPECT_EQ(rows30[0], rows[0]);
  for (std::size_t k = 0; k < 91; ++k) {
    const auto& sampled = rows30[1 + k];
    const auto& recorded = rows[1 + 4 * k];
    ASSERT_EQ(sampled.size(), recorded.size());
    EXPECT_EQ(sampled[0], std::to_string(k));
    EXPECT_NEAR(std::stod(sampled[1]), 1.0 + static_cast<double>(k) / 30.0, 1e-5);
    EXPECT_EQ(sampled[2], "15");
    for (std::size_t col = 3; col < sampled.size(); ++col) {
      // Quaternions may come out negated (the same rotation); positions and gaze must agree.
      const double s = std::stod(sampled[col]);
      const double r = std::stod(recorded[col]);
      const bool quaternion = rows[0][col].find("_q") != std::string::npos;
      // 1e-4: the file's frame time, .0083333, is 3e-9 s short of 1/120 s, so sample k falls
      // 4e-7 x 4k frames past recorded frame 4k, and the CSV has 6 significant digits.
      EXPECT_NEAR(quaternion ? std::abs(s) : s, quaternion ? std::abs(r) : r, 1e-4)
          << rows[0][col] << " at sample " << k;
    }
  }
  for (std::size_t k = 1; k + 1 < rows45.size(); ++k) {
    EXPECT_NEAR(std::stod(rows45[k + 1][1]) - std::stod(rows45[k][1]), 1.0 / 45.0, 1e-5);
    for (const std::string& cell : rows45[k]) {
      EXPECT_TRUE(std::isfinite(std::stod(cell))) << cell;
    }
  }
  Deixis zero({"capture", "bvh", kCmu.string(), "--rate", "0"});
  EXPECT_NE(zero.wait(), 0);
  EXPECT_NE(zero.err().find("--rate"), std::string::npos) << zero.err();
}

TEST(CaptureBvhCli, BadFlagsAndFilesExit2NamingThem) {
  deixis::testing::ScratchDir dir;
  const fs::path bad = dir.path() / "bad.bvh";
  std::ofstream(bad) << "HIERARCHY\nROOT r\n{\n OFFSET 0 0 0\n CHANNELS 1 Wposition\n}\n";
  Deixis file({"capture", "bvh", bad.string()});
  EXPECT_EQ(file.wait(), 2);
  EXPECT_NE(file.err().find("bad.bvh:5: unknown channel 'Wposition'"), std::string::npos)
      << file.err();
  Deixis unit({"capture", "bvh", bad.string(), "--unit", "feet"});
  EXPECT_NE(unit.wait(), 0);
  EXPECT_NE(unit.err().find("--unit"), std::string::npos) << unit.err();
  Deixis missing({"capture", "bvh", (dir.path() / "none.bvh").string()});
  EXPECT_NE(missing.wait(), 0);
  EXPECT_NE(missing.err().find("none.bvh"), std::string::npos) << missing.err();
}

}  // namespace
}  // namespace deixis::app
