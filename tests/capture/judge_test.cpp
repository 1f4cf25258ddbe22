// The authors' MPNet MoE, trained on real people, recognises the progressions of the capture's
// test subjects (aim: MPE ≤ 0.10), and the preview writes a PNG.

#include <gtest/gtest.h>

#include <fstream>

#include "capture/generate.h"
#include "capture/judge.h"
#include "capture/preview.h"
#include "capture/raster.h"
#include "core/error.h"
#include "gesture/features.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

namespace fs = std::filesystem;

TEST(Judge, TheAuthorsMpnetAgreesWithTheLabelsOfEveryTestSubject) {
  deixis::testing::ScratchDir dir;
  GenerateOptions o;
  o.out_dir = dir.path();
  o.sets = {"test"};
#ifdef DEIXIS_SANITIZED
  // Sanitizers check memory, not statistics: one right- and one left-handed subject, one
  // sequence per category (the networks run ~40× slower instrumented).
  o.subjects = {"161", "173"};
  o.count_scale = 0.001;
#else
  o.count_scale = 0.1;  // a tenth of the test set: 1–3 sequences per category and subject
#endif
  generate_datasets(o, [](const std::string&, std::size_t, std::size_t, std::size_t) {});
  JudgeOptions j;
  j.dataset_dir = dir.path();
  j.reference_dir = deixis::testing::reference_dir();
  const std::vector<SubjectVerdict> verdicts = judge(j);
  ASSERT_EQ(verdicts.size(), o.subjects.empty() ? 5u : o.subjects.size());
  for (const SubjectVerdict& v : verdicts) {
    EXPECT_EQ(v.left_handed, v.subject == "173" || v.subject == "174");
    EXPECT_LE(v.all.total(), 0.10) << "subject " << v.subject;
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(v.all.channel(k), 0.15) << "subject " << v.subject << " channel " << k;
    }
  }
}

TEST(Judge, AMismatchedLabelIsSeen) {
  // The judge is not blind: the same rows against shifted labels give a clearly worse MPE.
  const Sequence s = clean_sequence(1, "test", find_subject("172"), Category::kPointingSingle, 0);
  std::vector<float> rows;
  for (const TrackingFrame& f : s.frames) {
    const MpnetFeatureRow r = mpnet_features(f, s.calibration);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  const nn::Mpnet net =
      nn::Mpnet::load(authors_checkpoint(deixis::testing::reference_dir(), Hand::kRight));
  const std::vector<Labels> p = predict_progressions(net, rows);
  double right = 0;
  double shifted = 0;
  const std::size_t lag = 20;
  for (std::size_t i = 0; i + lag < s.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      right += static_cast<double>(std::abs(p[i][k] - s.labels[i][k]));
      shifted += static_cast<double>(std::abs(p[i][k] - s.labels[i + lag][k]));
    }
  }
  EXPECT_GT(shifted, 2 * right);
}

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
}  // namespace deixis::capture
