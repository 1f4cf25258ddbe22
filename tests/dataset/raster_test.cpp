// The rasteriser of the previews and figures (dataset/raster.h) covers the pixels it should.

#include <gtest/gtest.h>

#include "dataset/raster.h"

namespace deixis::dataset {
namespace {

TEST(Raster, LinesCirclesAndTextCoverTheirPixels) {
  Canvas c(40, 30, Rgb{255, 255, 255});
  c.line(2, 5.5f, 37, 5.5f, Rgb{0, 0, 0}, 1.0f);  // through the centres of row 5
  EXPECT_LT(c.at(20, 5).r, 100);
  EXPECT_EQ(c.at(20, 15).r, 255);
  c.disc(20, 20, 4, Rgb{255, 0, 0});
  EXPECT_EQ(c.at(20, 20).g, 0);
  c.clip(0, 0, 10, 10);
  c.rect(0, 0, 40, 30, Rgb{0, 0, 255});
  EXPECT_EQ(c.at(5, 8).r, 0);
  EXPECT_EQ(c.at(30, 25).b, 255);
  EXPECT_EQ(c.at(30, 25).r, 255);  // outside the clip: untouched
  c.reset_clip();
  Canvas t(60, 20, Rgb{255, 255, 255});
  t.text(2, 2, "Hi", Rgb{0, 0, 0});
  int ink = 0;
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 60; ++x) {
      ink += t.at(x, y).r == 0;
    }
  }
  EXPECT_GT(ink, 10);
}

}  // namespace
}  // namespace deixis::dataset
