#pragma once
// The `deixis` subcommands. main.cpp parses flags (CLI11, one translation unit); each command's
// work lives in its own file and returns the process exit code.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace deixis::app {

struct ParityOptions {
  std::vector<std::filesystem::path> fixtures;
  std::filesystem::path reference_dir;
};
int run_parity(const ParityOptions& options);

// `deixis avatar generate`: writes the default avatar (avatar/default_avatar.h) as .glb.
struct AvatarGenerateOptions {
  float height = 1.70f;      // m
  float arm_length = 0.74f;  // m
  std::filesystem::path output;
};
int run_avatar_generate(const AvatarGenerateOptions& options);

// `deixis avatar info`: loads avatars as Deixis does and prints their bones and measurements.
struct AvatarInfoOptions {
  std::vector<std::filesystem::path> files;
};
int run_avatar_info(const AvatarInfoOptions& options);

// `deixis capture …`: the synthetic capture (capture/, DESIGN §7).
struct CaptureGenerateOptions {
  std::filesystem::path out_dir;
  std::uint64_t seed = 1;
  std::vector<std::string> sets;      // train, test, validation; empty: all
  std::vector<std::string> subjects;  // empty: every subject of the chosen sets
  double count_scale = 1.0;
  std::string train_noise = "mocap";
  std::string test_noise = "headset";
};
int run_capture_generate(const CaptureGenerateOptions& options);

struct CapturePreviewOptions {
  std::string subject = "170";
  std::string category = "pointing-single";
  int index = 0;
  std::uint64_t seed = 1;
  std::string set = "train";
  std::string noise;  // empty: the set's default
  bool with_mpnet = false;
  std::filesystem::path reference_dir;
  std::filesystem::path output;
};
int run_capture_preview(const CapturePreviewOptions& options);

struct CaptureCsvOptions {
  std::filesystem::path dataset;
  long sequence = -1;            // -1: all
  std::filesystem::path output;  // empty: standard output
};
int run_capture_csv(const CaptureCsvOptions& options);

struct CaptureJudgeOptions {
  std::filesystem::path dataset_dir;
  std::filesystem::path reference_dir;
  std::vector<std::string> subjects;
  double max_mpe = -1;  // exit 1 when the overall MPE is above it; < 0: report only
};
int run_capture_judge(const CaptureJudgeOptions& options);

}  // namespace deixis::app
