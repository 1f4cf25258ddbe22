#include "capture/generate.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "capture/mirror.h"
#include "capture/random.h"
#include "capture/script.h"
#include "capture/speed.h"
#include "capture/targets.h"
#include "capture/tracker_noise.h"
#include "core/error.h"
#include "dataset/dataset.h"
#include "gesture/features.h"

namespace deixis::capture {

namespace {

constexpr std::array<float, 3> kAugmentedSpeeds = {1.0f, 0.5f, 2.0f};

struct Plan {
  std::string set;
  const Subject* subject;
  std::string noise;
};

int scaled_count(int count, double scale) {
  return std::max(1, static_cast<int>(std::lround(count * scale)));
}

std::string categories_list() {
  std::string out;
  for (const Category c : kAllCategories) {
    if (!out.empty()) {
      out.push_back(',');
    }
    out.append(category_name(c));
  }
  return out;
}

// A recording into a dataset, with the network columns computed by the runtime's own feature code
// (gesture/features.h). Dropped parts already hold their last valid values (tracker_noise.h), as
// the runtime holds them.
void add_recording(dataset::DatasetWriter& w, const Sequence& s, std::int32_t source) {
  static_assert(dataset::kFeatureColumns == kMpnetFeatureCount);
  static_assert(dataset::kTargetFeatureColumn == mf::kTarget);
  std::vector<float> features;
  std::vector<float> poses;
  features.reserve(s.size() * kMpnetFeatureCount);
  poses.reserve(s.size() * kEndEffectorSize);
  for (const TrackingFrame& f : s.frames) {
    const MpnetFeatureRow row = mpnet_features(f, s.calibration);
    features.insert(features.end(), row.begin(), row.end());
    const EndEffectors x = end_effectors(f, s.calibration);
    poses.insert(poses.end(), x.begin(), x.end());
  }
  dataset::SequenceRows rows;
  rows.category = s.category;
  rows.source = source;
  rows.seed = s.seed;
  rows.speed = s.speed;
  rows.mirrored = s.mirrored;
  rows.body = s.calibration;
  rows.targets = s.targets;
  rows.frames = s.frames;
  rows.labels = s.labels;
  rows.phase_keys = s.phase_keys;
  rows.mpnet_features = features;
  rows.end_effectors = poses;
  w.add(rows);
}

std::string elevation_range(const TargetRules& rules) {
  return std::to_string(static_cast<int>(rules.pointing_elevation_min_deg)) + "," +
         std::to_string(static_cast<int>(rules.pointing_elevation_max_deg));
}

// A category's sequences in a set at a count scale: the first range's, then (training set,
// pointing categories) the low-target additions.
struct CategoryCounts {
  int first = 0;
  int low = 0;
};

CategoryCounts category_counts(std::string_view set, Category c, double count_scale,
                               bool low_targets = true) {
  const bool training = set == kTrainingSet;
  const int first = scaled_count(training ? training_count(c) : test_count(c), count_scale);
  return {first, training && low_targets ? low_target_count(c, first) : 0};
}

void describe(dataset::DatasetWriter& w, const Plan& plan, const GenerateOptions& options,
              bool mirrored) {
  const Subject& s = *plan.subject;
  const bool left = (s.handedness == Hand::kLeft) != mirrored;
  w.set_metadata("set", plan.set);
  w.set_metadata("subject", s.name);
  w.set_metadata("deictic_hand", left ? "left" : "right");
  w.set_metadata("mirrored", mirrored ? "1" : "0");
  w.set_metadata("dominant_eye", (s.dominant_eye == Eye::kRight) != mirrored ? "right" : "left");
  w.set_metadata("height", std::to_string(s.height));
  w.set_metadata("arm_length", std::to_string(s.arm_length));
  w.set_metadata("shoulder_width", std::to_string(s.shoulder_width));
  w.set_metadata("speed", std::to_string(s.speed));
  w.set_metadata("tracker_noise", plan.noise);
  w.set_metadata("seed", std::to_string(options.seed));
  w.set_metadata("count_scale", std::to_string(options.count_scale));
  w.set_metadata("pointing_elevation_deg", elevation_range(TargetRules{}));
  if (plan.set == kTrainingSet) {
    int low = 0;
    for (const Category c : kAllCategories) {
      low += category_counts(plan.set, c, options.count_scale, options.low_targets).low;
    }
    if (low > 0) {  // tools/run train looks for this key: a capture without it is rewritten
      w.set_metadata("low_pointing_elevation_deg", elevation_range(low_target_rules()));
    }
    w.set_metadata("low_pointing_sequences", std::to_string(low));
  }
  w.set_metadata("categories", categories_list());
  w.set_metadata("labels", "gaze,deictic,idle");
  w.set_metadata("frame_rate", "30");
  w.set_metadata("clip_length", "45");
  w.set_metadata("clip_hop", "7");
}

std::vector<Plan> plans(const GenerateOptions& options) {
  for (const std::string& set : options.sets) {
    if (set != kTrainingSet && set != kTestSet && set != kValidationSet) {
      throw Error("unknown set '" + set + "' (known: train, test, validation)");
    }
  }
  for (const std::string& name : options.subjects) {
    find_subject(name);  // throws for an unknown subject
  }
  auto wanted = [&](const Subject& s) {
    return options.subjects.empty() || std::find(options.subjects.begin(), options.subjects.end(),
                                                 s.name) != options.subjects.end();
  };
  auto has = [&](std::string_view set) {
    return std::find(options.sets.begin(), options.sets.end(), set) != options.sets.end();
  };
  std::vector<Plan> out;
  if (has(kTrainingSet) && wanted(training_subject())) {
    out.push_back({std::string(kTrainingSet), &training_subject(), options.train_noise});
  }
  for (const auto& [set, list] :
       {std::pair{kTestSet, test_subjects()}, std::pair{kValidationSet, validation_subjects()}}) {
    if (!has(set)) {
      continue;
    }
    for (const Subject& s : list) {
      if (wanted(s)) {
        out.push_back({std::string(set), &s, options.test_noise});
      }
    }
  }
  if (out.empty()) {
    throw Error("nothing to generate: no subject of the chosen sets matches --subjects");
  }
  return out;
}

}  // namespace

int training_count(Category c) {
  switch (c) {
    case Category::kPointingSingle:
      return 81;
    case Category::kPointingTwoTargets:
      return 210;
    case Category::kPointingGazeShift:
      return 180;
    case Category::kPointingExplanation:
      return 126;
    case Category::kPointingTransition:
      return 30;
    case Category::kTouchingSingle:
      return 90;
    case Category::kTouchingGazeShift:
      return 210;
    case Category::kTouchingExplanation:
      return 126;
    case Category::kTouchingTwoTargets:
      return 210;
    case Category::kTouchingTransition:
      return 27;
  }
  return 0;
}

int test_count(Category c) {
  switch (c) {
    case Category::kPointingSingle:
    case Category::kPointingTransition:
    case Category::kTouchingTransition:
      return 27;
    case Category::kTouchingSingle:
      return 30;
    default:
      return 8;
  }
}

std::uint64_t sequence_seed(std::uint64_t seed, std::string_view set, std::string_view subject,
                            Category category, int index) {
  std::uint64_t s = combine_seed(seed, hash_name(set));
  s = combine_seed(s, hash_name(subject));
  return combine_seed(
      s, static_cast<std::uint64_t>(category) * 1'000'003ull + static_cast<std::uint64_t>(index));
}

std::uint64_t noise_seed(std::uint64_t sequence_seed, float speed) {
  return combine_seed(sequence_seed, static_cast<std::uint64_t>(std::lround(speed * 4.0f)));
}

int low_target_count(Category c, int count) {
  if (is_touching(c)) {
    return 0;
  }
  const TargetRules first;
  const TargetRules low = low_target_rules();
  const double share = (low.pointing_elevation_max_deg - low.pointing_elevation_min_deg) /
                       (first.pointing_elevation_max_deg - first.pointing_elevation_min_deg);
  return static_cast<int>(std::lround(count * share));
}

Sequence clean_sequence(std::uint64_t seed, std::string_view set, const Subject& subject,
                        Category category, int index, double count_scale) {
  const CategoryCounts counts = category_counts(set, category, count_scale);
  const bool low = counts.low > 0 && index >= counts.first;
  return perform(subject, category, sequence_seed(seed, set, subject.name, category, index),
                 low ? low_target_rules() : TargetRules{});
}

std::vector<GeneratedFile> generate_datasets(const GenerateOptions& options,
                                             const GenerateProgress& progress) {
  if (!(options.count_scale > 0.0) || options.count_scale > 100.0) {
    throw Error("count scale must be in (0, 100], got " + std::to_string(options.count_scale));
  }
  const TrackerNoise train_noise = tracker_noise(options.train_noise);
  const TrackerNoise test_noise = tracker_noise(options.test_noise);
  const std::vector<Plan> all = plans(options);
  std::filesystem::create_directories(options.out_dir);

  std::vector<GeneratedFile> written;
  for (const Plan& plan : all) {
    const auto started = std::chrono::steady_clock::now();
    const bool training = plan.set == kTrainingSet;
    const TrackerNoise& noise = training ? train_noise : test_noise;
    const std::string name =
        training ? std::string("train_right") : plan.set + "_" + plan.subject->name;
    dataset::DatasetWriter writer;
    dataset::DatasetWriter mirrored;
    describe(writer, plan, options, false);
    describe(mirrored, plan, options, true);

    std::size_t total = 0;
    for (const Category c : kAllCategories) {
      const CategoryCounts n =
          category_counts(plan.set, c, options.count_scale, options.low_targets);
      total += static_cast<std::size_t>(n.first + n.low);
    }
    std::size_t done = 0;
    for (const Category c : kAllCategories) {
      const CategoryCounts n =
          category_counts(plan.set, c, options.count_scale, options.low_targets);
      for (int i = 0; i < n.first + n.low; ++i) {
        const Sequence clean =
            clean_sequence(options.seed, plan.set, *plan.subject, c, i, options.count_scale);
        const std::int32_t source = writer.next_index();
        const bool augment = training && is_speed_augmented(c);
        for (const float speed : kAugmentedSpeeds) {
          if (speed != 1.0f && !augment) {
            continue;
          }
          Sequence s = speed == 1.0f ? clean : resample_speed(clean, speed);
          s.joints.clear();
          apply_tracker_noise(s, noise, noise_seed(clean.seed, speed));
          add_recording(writer, s, source);
          if (training) {
            add_recording(mirrored, mirror(s), source);
          }
        }
        progress(name, ++done, total, writer.frames());
      }
    }
    const std::size_t first = written.size();
    const std::filesystem::path path = options.out_dir / (name + ".safetensors");
    writer.write(path);
    written.push_back({path, static_cast<std::size_t>(writer.next_index()), writer.frames(), 0});
    if (training) {
      const std::filesystem::path left = options.out_dir / "train_left.safetensors";
      mirrored.write(left);
      written.push_back(
          {left, static_cast<std::size_t>(mirrored.next_index()), mirrored.frames(), 0});
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    for (std::size_t k = first; k < written.size(); ++k) {
      written[k].seconds = seconds;  // a training file and its mirror are made together
    }
  }
  return written;
}

}  // namespace deixis::capture
