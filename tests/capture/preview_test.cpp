// The preview of a sequence (`deixis capture preview`) writes a PNG, and refuses what it cannot
// draw.

#include <gtest/gtest.h>

#include <fstream>

#include "capture/generate.h"
#include "capture/preview.h"
#include "core/error.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

namespace fs = std::filesystem;

TEST(Preview, WritesAPngWithCurvesAndViews) {
  deixis::testing::ScratchDir dir;
  const Sequence s =
      clean_sequence(1, "train", find_subject("170"), Category::kTouchingExplanation, 0);
  const fs::path png = dir.path() / "preview.png";
  write_preview(s, nullptr, "test", png);
  std::ifstream in(png, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
  Sequence without_skeleton = s;
  without_skeleton.joints.clear();
  EXPECT_THROW(write_preview(without_skeleton, nullptr, "x", png), Error);
  EXPECT_THROW(write_preview(s, nullptr, "x", dir.path() / "missing" / "x.png"), Error);
}

}  // namespace
}  // namespace deixis::capture
