#pragma once
// `deixis eval` as a library call: every row of the paper's Tables I–IV (and the robustness
// behind Fig. 5) for every weight set, on the held-out subjects' test sets, with per-subject
// breakdowns. The command (app/eval_command.cpp) only parses flags and writes the files.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "eval/runs.h"
#include "eval/tables.h"

namespace deixis::eval {

// A directory with right/ and left/ holding networks under the authors' file names
// (MPNet(MoE)(AC)80.safetensors, UGNet(Diffusion)(AC)120.safetensors, …).
struct WeightSet {
  std::string label;  // "authors", "deixis"
  std::filesystem::path dir;
};

struct EvalOptions {
  std::filesystem::path data_dir;     // test_<subject>.safetensors
  std::vector<std::string> subjects;  // empty: every test file in data_dir
  std::vector<WeightSet> weights;
  // The FMD motion encoder: <dir>/{right,left}/AutoEncoder.safetensors (deixis-train
  // autoencoder). Empty: looked for in each weight set's directory; none found → FMD is n/a.
  std::filesystem::path encoder_dir;
  bool quick = false;
  // Units of work (a subject's rows of one weight set) run this many at a time; 0: one per core.
  // The report is the same for any count (tests/eval/eval_test.cpp).
  int threads = 0;
  Sampling sampling;
  std::string command;  // recorded in the report
  std::function<void(const std::string&)> progress;
};

// The protocol's sampling (all pairs, docs/eval.md#sampling-and-time) and the tiny one of --quick.
Sampling full_sampling();
Sampling quick_sampling();

// Runs everything; errors (unreadable or training-subject data, corrupt weights) are
// deixis::Error naming the file. Missing weight files leave their rows n/a with a note.
Report evaluate(const EvalOptions& options);

}  // namespace deixis::eval
