// `deixis capture generate|preview|csv|judge|bvh`: the synthetic capture's datasets, a picture of
// one sequence, a CSV view of a dataset, the authors' MPNet as a judge of the test sets, and the
// tracking a BVH recording gives (docs/bvh.md).
// Exit codes: 0 done, 1 the judge's MPE is above --max-mpe, 2 bad parameters or files.

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "app/commands.h"
#include "capture/generate.h"
#include "capture/preview.h"
#include "capture/tracker_noise.h"
#include "core/error.h"
#include "dataset/csv.h"
#include "dataset/dataset.h"
#include "eval/judge.h"
#include "gesture/features.h"
#include "mocap/bvh.h"
#include "mocap/player.h"
#include "mocap/skeleton_tracking.h"

namespace deixis::app {

namespace {

using namespace deixis::capture;
using dataset::Dataset;
using eval::authors_checkpoint;
using eval::judge;
using eval::JudgeOptions;
using eval::MpeSum;
using eval::predict_progressions;
using eval::SubjectVerdict;

int fail(const char* command, const std::exception& e) {
  std::fprintf(stderr, "deixis capture %s: %s\n", command, e.what());
  return 2;
}

std::string default_noise(const std::string& set) {
  return set == kTrainingSet ? "mocap" : "headset";
}

void print_table(const std::vector<SubjectVerdict>& verdicts) {
  std::printf(
      "\nMPE of the authors' MPNet MoE (AC) on the capture's test subjects "
      "(mean |p - p^| over gaze, deictic, idle; paper Table III: 0.054)\n\n");
  std::printf("| category | %s", "");
  for (const SubjectVerdict& v : verdicts) {
    std::printf("%s%s | ", v.subject.c_str(), v.left_handed ? " (L)" : "");
  }
  std::printf("all |\n|---|");
  for (std::size_t k = 0; k <= verdicts.size(); ++k) {
    std::printf("---:|");
  }
  std::printf("\n");
  for (const Category c : kAllCategories) {
    MpeSum sum;
    std::printf("| %s | ", std::string(category_name(c)).c_str());
    for (const SubjectVerdict& v : verdicts) {
      const MpeSum& m = v.categories[static_cast<std::size_t>(c)];
      sum.add(m);
      std::printf("%.3f | ", m.total());
    }
    std::printf("%.3f |\n", sum.total());
  }
  MpeSum all;
  std::printf("| **all** | ");
  for (const SubjectVerdict& v : verdicts) {
    all.add(v.all);
    std::printf("**%.3f** | ", v.all.total());
  }
  std::printf("**%.3f** |\n\n", all.total());
  std::printf("per channel, all subjects: gaze %.3f, deictic %.3f, idle %.3f (%zu frames)\n",
              all.channel(0), all.channel(1), all.channel(2), all.frames);
}

}  // namespace

int run_capture_generate(const CaptureGenerateOptions& o) {
  try {
    GenerateOptions options;
    options.out_dir = o.out_dir;
    options.seed = o.seed;
    if (!o.sets.empty()) {
      options.sets = o.sets;
    }
    options.subjects = o.subjects;
    options.count_scale = o.count_scale;
    options.low_targets = o.low_targets;
    options.train_noise = o.train_noise;
    options.test_noise = o.test_noise;
    const auto started = std::chrono::steady_clock::now();
    std::size_t last_step = 0;
    std::string last_file;
    const auto progress = [&](const std::string& file, std::size_t done, std::size_t total,
                              std::size_t frames) {
      const std::size_t step = done * 10 / total;
      if (file != last_file || step != last_step || done == total) {
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        std::fprintf(stderr, "  %-22s %5zu/%zu sequences  %8zu frames  %6.1f s\n", file.c_str(),
                     done, total, frames, seconds);
        last_file = file;
        last_step = step;
      }
    };
    std::fprintf(stderr, "deixis capture generate: writing to %s (seed %llu)\n",
                 o.out_dir.string().c_str(), static_cast<unsigned long long>(o.seed));
    const std::vector<GeneratedFile> files = generate_datasets(options, progress);
    std::printf("| file | sequences | frames | seconds |\n|---|---:|---:|---:|\n");
    for (const GeneratedFile& f : files) {
      std::printf("| %s | %zu | %zu | %.1f |\n", f.path.filename().string().c_str(), f.sequences,
                  f.frames, f.seconds);
    }
    return 0;
  } catch (const std::exception& e) {
    return fail("generate", e);
  }
}

int run_capture_preview(const CapturePreviewOptions& o) {
  try {
    const Subject& subject = find_subject(o.subject);
    const Category category = dataset::parse_category(o.category);
    if (o.set != kTrainingSet && o.set != kTestSet && o.set != kValidationSet) {
      throw Error("unknown set '" + o.set + "' (known: train, test, validation)");
    }
    if (o.index < 0) {
      throw Error("--index must be ≥ 0, got " + std::to_string(o.index));
    }
    const Sequence clean = clean_sequence(o.seed, o.set, subject, category, o.index);
    std::vector<Labels> predictions;
    std::string noise_name = o.noise.empty() ? default_noise(o.set) : o.noise;
    if (o.with_mpnet) {
      Sequence tracked = clean;
      apply_tracker_noise(tracked, tracker_noise(noise_name), noise_seed(clean.seed, 1.0f));
      std::vector<float> rows;
      for (const TrackingFrame& f : tracked.frames) {
        const MpnetFeatureRow r = mpnet_features(f, tracked.calibration);
        rows.insert(rows.end(), r.begin(), r.end());
      }
      const Hand hand = subject.handedness;
      const nn::Mpnet net = nn::Mpnet::load(authors_checkpoint(o.reference_dir, hand));
      predictions = predict_progressions(net, rows);
    }
    char title[256];
    std::snprintf(title, sizeof title,
                  "subject %s (%s-handed, %s eye)  %s #%d  %s set, seed %llu%s",
                  subject.name.c_str(), subject.handedness == Hand::kRight ? "right" : "left",
                  subject.dominant_eye == Eye::kRight ? "right" : "left",
                  std::string(category_name(category)).c_str(), o.index, o.set.c_str(),
                  static_cast<unsigned long long>(o.seed),
                  o.with_mpnet ? (", tracker noise " + noise_name).c_str() : "");
    write_preview(clean, o.with_mpnet ? &predictions : nullptr, title, o.output);
    std::printf("wrote %s (%zu frames, %.1f s)\n", o.output.string().c_str(), clean.size(),
                clean.frames.back().time);
    return 0;
  } catch (const std::exception& e) {
    return fail("preview", e);
  }
}

int run_capture_csv(const CaptureCsvOptions& o) {
  try {
    const Dataset d = Dataset::read(o.dataset);
    std::optional<std::size_t> sequence;
    if (o.sequence >= 0) {
      sequence = static_cast<std::size_t>(o.sequence);
    }
    if (o.output.empty()) {
      write_csv(d, sequence, std::cout);
      return 0;
    }
    std::ofstream out(o.output);
    if (!out) {
      throw Error(o.output.string() + ": cannot open for writing");
    }
    write_csv(d, sequence, out);
    if (!out) {
      throw Error(o.output.string() + ": write failed");
    }
    return 0;
  } catch (const std::exception& e) {
    return fail("csv", e);
  }
}

namespace {

// The tracking columns of `deixis capture csv` (dataset/csv.cpp) that a recording has: no
// sequence, category, phase, targets, labels or network columns (docs/bvh.md#the-command).
void write_bvh_header(std::ostream& out) {
  out << "frame,time,valid";
  dataset::write_tracking_column_names(out);
  out << '\n';
}

void write_bvh_row(std::ostream& out, std::size_t frame, const TrackingFrame& f) {
  char buffer[32];
  auto put = [&](double v) {
    std::snprintf(buffer, sizeof buffer, ",%.6g", v);
    out << buffer;
  };
  auto vec = [&](const Vec3& v) {
    for (int k = 0; k < 3; ++k) {
      put(static_cast<double>(v[k]));
    }
  };
  auto quat = [&](const Mat3& R) {
    const Quat q(R);
    for (const float v : {q.x(), q.y(), q.z(), q.w()}) {
      put(static_cast<double>(v));
    }
  };
  out << frame;
  put(f.time);
  out << ',' << static_cast<int>(f.valid);
  vec(f.T_world_head.translation);
  quat(f.T_world_head.rotation);
  vec(f.gaze);
  for (std::size_t h = 0; h < 2; ++h) {
    vec(f.T_world_wrist[h].translation);
    quat(f.T_world_wrist[h].rotation);
    vec(f.index_tip[h]);
  }
  out << '\n';
}

// --rate: the tracking at `rate` Hz from frame `first`'s time to frame `last` − 1's, through the
// player's interpolation (mocap/player.h); row k is sample k, its time the recording's.
void write_resampled(std::ostream& out, const mocap::Bvh& bvh, double metres_per_unit,
                     std::size_t first, std::size_t last, double rate) {
  mocap::BvhPlayer player(bvh, metres_per_unit, mocap::Playback::kOnce);
  const double start = static_cast<double>(first) * bvh.frame_time;
  const double span = static_cast<double>(last - 1 - first) * bvh.frame_time;
  const auto count = mocap::sample_count(span, rate);
  TrackingFrame f;
  for (std::size_t k = 0; k < count; ++k) {
    player.at(start + static_cast<double>(k) / rate, f);
    write_bvh_row(out, k, f);
  }
}

}  // namespace

int run_capture_bvh(const CaptureBvhOptions& o) {
  try {
    const mocap::Bvh bvh = mocap::read_bvh(o.file);
    mocap::LengthUnit unit = mocap::parse_length_unit(o.unit);
    if (unit == mocap::LengthUnit::kAuto) {
      unit = mocap::infer_unit(bvh);
    }
    const std::size_t frames = bvh.frames();
    const std::size_t first = static_cast<std::size_t>(o.from);
    const std::size_t last = o.to < 0 ? frames : static_cast<std::size_t>(o.to);
    if (first >= last || last > frames) {
      throw Error("--from " + std::to_string(o.from) + " --to " + std::to_string(o.to) +
                  ": the recording has frames 0 to " + std::to_string(frames - 1));
    }
    mocap::SkeletonTracking tracking(bvh, mocap::metres_per_unit(unit));
    const BodyCalibration c = tracking.calibrate();
    std::fprintf(stderr,
                 "deixis capture bvh: %s: %zu frames at %.1f Hz, unit %s (rest pose %.3f m), "
                 "height %.3f m, arm %.3f m (from frame %zu)\n",
                 o.file.string().c_str(), frames, 1.0 / bvh.frame_time,
                 std::string(mocap::unit_name(unit)).c_str(), tracking.rest_stature(),
                 static_cast<double>(c.height), static_cast<double>(c.arm_length),
                 tracking.upright_frame());
    if (o.rate > 0.0) {
      std::fprintf(stderr,
                   "deixis capture bvh: resampled at %.6g Hz (the player's interpolation)\n",
                   o.rate);
    }
    std::ofstream file;
    if (!o.csv.empty()) {
      file.open(o.csv);
      if (!file) {
        throw Error(o.csv.string() + ": cannot open for writing");
      }
    }
    std::ostream& out = o.csv.empty() ? std::cout : file;
    write_bvh_header(out);
    if (o.rate > 0.0) {
      write_resampled(out, bvh, mocap::metres_per_unit(unit), first, last, o.rate);
    } else {
      TrackingFrame f;
      const std::size_t step = std::max<std::size_t>(1, (last - first) / 10);
      for (std::size_t i = first; i < last; ++i) {
        tracking.track(i, f);
        write_bvh_row(out, i, f);
        if ((last - first) > 10000 && (i - first) % step == 0) {
          std::fprintf(stderr, "  frame %zu of %zu\n", i - first, last - first);
        }
      }
    }
    if (!out) {
      throw Error((o.csv.empty() ? std::string("stdout") : o.csv.string()) + ": write failed");
    }
    return 0;
  } catch (const std::exception& e) {
    return fail("bvh", e);
  }
}

int run_capture_judge(const CaptureJudgeOptions& o) {
  try {
    JudgeOptions options;
    options.dataset_dir = o.dataset_dir;
    options.reference_dir = o.reference_dir;
    options.subjects = o.subjects;
    std::fprintf(stderr, "deixis capture judge: running the authors' MPNet on %s\n",
                 o.dataset_dir.string().c_str());
    const std::vector<SubjectVerdict> verdicts = judge(options);
    print_table(verdicts);
    MpeSum all;
    for (const SubjectVerdict& v : verdicts) {
      all.add(v.all);
    }
    if (o.max_mpe >= 0 && all.total() > o.max_mpe) {
      std::printf("MPE %.3f is above --max-mpe %.3f\n", all.total(), o.max_mpe);
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    return fail("judge", e);
  }
}

}  // namespace deixis::app
