// Where the capture puts pointing targets (capture/targets.h, generate.h): every set's first
// sequences stay within −25° to +30°, the training set's added pointing sequences (indices from
// the category's count on) reach 25° to 50° below the eyes (decisions 87 and 89).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "capture/generate.h"
#include "capture/script.h"
#include "capture/subject.h"
#include "core/io/safetensors.h"
#include "core/math/angles.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

struct ElevationRange {
  float lowest = 90.0f, highest = -90.0f;
};

// Elevations (degrees) of every pointing target from the person's eyes as they stand at the start.
ElevationRange pointing_elevations(const Sequence& s, ElevationRange r) {
  const Vec3 eyes = s.frames.front().T_world_head.translation;
  for (const TargetObject& t : s.targets) {
    if (t.id == kPartnerTarget) {
      continue;
    }
    const Vec3 d = t.position - eyes;
    const float elevation = std::atan2(d.y(), std::hypot(d.x(), d.z())) * kDegPerRad;
    r.lowest = std::min(r.lowest, elevation);
    r.highest = std::max(r.highest, elevation);
  }
  return r;
}

ElevationRange over_sequences(std::string_view set, int first, int last) {
  ElevationRange r;
  for (int i = first; i < last; ++i) {
    r = pointing_elevations(
        clean_sequence(1, set, find_subject("170"), Category::kPointingTwoTargets, i), r);
  }
  return r;
}

// A few degrees of slack: the sampler measures from the stance's eye height, the check from the
// tracked head at the first frame.
constexpr float kSlackDeg = 3.0f;

void expect_within(const ElevationRange& r, const TargetRules& rules, const char* what) {
  std::printf("%s: pointing elevations %.1f..%.1f deg\n", what, static_cast<double>(r.lowest),
              static_cast<double>(r.highest));
  EXPECT_GE(r.lowest, rules.pointing_elevation_min_deg - kSlackDeg) << what;
  EXPECT_LE(r.highest, rules.pointing_elevation_max_deg + kSlackDeg) << what;
  // The range is used, not only respected: both ends are reached within 10°.
  EXPECT_LT(r.lowest, rules.pointing_elevation_min_deg + 10.0f) << what;
  EXPECT_GT(r.highest, rules.pointing_elevation_max_deg - 10.0f) << what;
}

TEST(CaptureTargets, FirstSequencesKeepTheFirstRangeAndAddedOnesPointLow) {
  const int count = training_count(Category::kPointingTwoTargets);
  const int added = low_target_count(Category::kPointingTwoTargets, count);
  expect_within(over_sequences(kTrainingSet, 0, 40), TargetRules{}, "training, first");
  expect_within(over_sequences(kTrainingSet, count - 20, count), TargetRules{},
                "training, last of the first range");
  expect_within(over_sequences(kTrainingSet, count, count + 40), low_target_rules(),
                "training, added");
  expect_within(over_sequences(kTestSet, 0, 40), TargetRules{}, "test");
  EXPECT_EQ(added, 95);  // 210 × 25/55
}

TEST(CaptureTargets, AddedCountsFollowTheElevationShare) {
  for (const Category c : kAllCategories) {
    const int count = training_count(c);
    const int added = low_target_count(c, count);
    if (is_touching(c)) {
      EXPECT_EQ(added, 0) << category_name(c);
    } else {
      EXPECT_NEAR(added, count * 25.0 / 55.0, 0.5) << category_name(c);
    }
  }
}

// The first sequences are the sequences the first captures recorded (same seed, same rules): the
// part of the training set the shipped weights came from is unchanged by the additions.
TEST(CaptureTargets, FirstSequencesAreTheFirstCapturesOnes) {
  const Subject& subject = find_subject("170");
  const int count = training_count(Category::kPointingSingle);
  for (const int i : {0, count - 1}) {
    const Sequence now = clean_sequence(1, kTrainingSet, subject, Category::kPointingSingle, i);
    const Sequence first =
        perform(subject, Category::kPointingSingle,
                sequence_seed(1, kTrainingSet, subject.name, Category::kPointingSingle, i), {});
    ASSERT_EQ(now.targets.size(), first.targets.size());
    for (std::size_t k = 0; k < now.targets.size(); ++k) {
      EXPECT_EQ(now.targets[k].position, first.targets[k].position);
    }
  }
}

// With a count scale, the additions start after the scaled count.
TEST(CaptureTargets, ScaledCapturesAddAfterTheScaledCount) {
  const Subject& subject = find_subject("170");
  const Category c = Category::kPointingTwoTargets;
  ElevationRange r;
  for (int i = 21; i < 31; ++i) {  // round(210 × 0.1) = 21 first, then round(21 × 25/55) = 10
    r = pointing_elevations(clean_sequence(1, kTrainingSet, subject, c, i, 0.1), r);
  }
  EXPECT_LE(r.highest, low_target_rules().pointing_elevation_max_deg + kSlackDeg);
}

// The training file says how many low-target sequences it holds and their range (tools/run
// train rewrites a capture without that range); --without-low-targets leaves them out.
TEST(CaptureTargets, TheTrainingFileNamesItsLowTargets) {
  deixis::testing::ScratchDir dir;
  GenerateOptions o;
  o.sets = {"train"};
  o.count_scale = 0.1;
  const auto quiet = [](const std::string&, std::size_t, std::size_t, std::size_t) {};
  for (const bool low : {true, false}) {
    o.low_targets = low;
    o.out_dir = dir.path() / (low ? "with" : "without");
    const std::vector<GeneratedFile> files = generate_datasets(o, quiet);
    const SafetensorsFile f = SafetensorsFile::read(o.out_dir / "train_right.safetensors");
    int added = 0;
    for (const Category c : kAllCategories) {
      const int count = std::max(1, static_cast<int>(std::lround(training_count(c) * 0.1)));
      added += low_target_count(c, count);
    }
    EXPECT_EQ(f.metadata().at("low_pointing_sequences"), std::to_string(low ? added : 0));
    EXPECT_EQ(f.metadata().contains("low_pointing_elevation_deg"), low);
    EXPECT_EQ(f.metadata().at("pointing_elevation_deg"), "-25,30");
    // Recordings: every sequence once, the speed-augmented categories' three times.
    std::size_t recordings = 0;
    for (const Category c : kAllCategories) {
      const int count = std::max(1, static_cast<int>(std::lround(training_count(c) * 0.1)));
      const int n = count + (low ? low_target_count(c, count) : 0);
      recordings += static_cast<std::size_t>(n * (is_speed_augmented(c) ? 3 : 1));
    }
    EXPECT_EQ(files.front().sequences, recordings);
    EXPECT_GT(added, 0);
  }
}

TEST(CaptureTargets, RulesAreWhatPerformUses) {
  TargetRules level;
  level.pointing_elevation_min_deg = -2.0f;
  level.pointing_elevation_max_deg = 2.0f;
  ElevationRange r;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    r = pointing_elevations(
        perform(find_subject("170"), Category::kPointingTwoTargets, seed, level), r);
  }
  EXPECT_GE(r.lowest, -2.0f - kSlackDeg);
  EXPECT_LE(r.highest, 2.0f + kSlackDeg);
}

}  // namespace
}  // namespace deixis::capture
