// The authors' MPNet MoE, trained on real people, recognises the progressions of the capture's
// test subjects (aim: MPE ≤ 0.10), and is not blind to wrong labels.

#include <gtest/gtest.h>

#include "capture/generate.h"
#include "eval/judge.h"
#include "gesture/features.h"
#include "test_support.h"

namespace deixis::eval {
namespace {

using capture::clean_sequence;
using capture::find_subject;
using capture::GenerateOptions;
using capture::Sequence;

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
  capture::generate_datasets(o, [](const std::string&, std::size_t, std::size_t, std::size_t) {});
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
  const Sequence s =
      clean_sequence(1, "test", find_subject("172"), dataset::Category::kPointingSingle, 0);
  std::vector<float> rows;
  for (const TrackingFrame& f : s.frames) {
    const MpnetFeatureRow r = mpnet_features(f, s.calibration);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  const nn::Mpnet net =
      nn::Mpnet::load(authors_checkpoint(deixis::testing::reference_dir(), Hand::kRight));
  const std::vector<dataset::Labels> p = predict_progressions(net, rows);
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

}  // namespace
}  // namespace deixis::eval
