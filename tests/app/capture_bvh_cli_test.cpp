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
