#pragma once
// Parity with the authors: runs one of their fixture files through our code and measures the
// largest absolute difference to every reference output the fixture holds: single-network
// fixtures through that network, chained rollout fixtures through the translation loop
// (docs/conventions.md#parity). Works on
// any fixture of that schema, including ones it has never seen: the network is chosen by the
// fixture's tensors, the checkpoint by its metadata ("checkpoint", relative to the reference
// directory).

#include <filesystem>
#include <string>
#include <vector>

namespace deixis {

struct ParityCheck {
  std::string tensor;        // the fixture's reference tensor, e.g. "output_preclamp"
  double max_abs_error = 0;  // over all its elements
  double tolerance = 0;
  std::size_t values = 0;
  bool passed() const { return max_abs_error <= tolerance; }
};

struct ParityReport {
  std::string fixture;
  std::string network;     // e.g. "MPNet GRU-MoE"
  std::string checkpoint;  // as resolved on disk
  int windows = 0;
  std::vector<ParityCheck> checks;
  bool passed() const;
};

// Tolerances for a float32 port (docs/conventions.md#parity).
inline constexpr double kMpnetTolerance = 5e-5;
inline constexpr double kDiffusionTolerance = 5e-5;
inline constexpr double kUgnetTolerance = 1e-5;
inline constexpr double kAmnetTolerance = 1e-5;
// The chained rollout's avatar pose (goal: within 1e-5 of the authors' 120 steps).
inline constexpr double kRolloutTolerance = 1e-5;

// Throws deixis::Error naming the file when the fixture is unreadable or of an unknown schema.
ParityReport check_parity(const std::filesystem::path& fixture,
                          const std::filesystem::path& reference_dir);

}  // namespace deixis
