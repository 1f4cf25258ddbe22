#pragma once
// `deixis eval --bvh FILE...` as a library call: every recording through every weight set's
// translator (eval/real_motion.h) and the figures laid out as the report's real-motion section
// (eval/tables.h), per recording and weight set side by side. Needs no synthetic test data.

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "eval/evaluation.h"
#include "eval/real_motion.h"

namespace deixis::eval {

struct RealMotionOptions {
  std::vector<std::filesystem::path> files;
  std::vector<WeightSet> weights;  // the set labelled "authors" is (c)'s reference
  std::function<void(const std::string&)> progress;
};

// The section for results already measured (one per recording, sets in the same order).
RealMotionSection real_motion_section(const std::vector<Recording>& recordings,
                                      const std::vector<RealMotionResult>& results);

// Reads every file first (a bad one is a deixis::Error naming file:line before any network
// runs), then measures. Weight files missing: deixis::Error naming the file.
RealMotionSection evaluate_real_motion(const RealMotionOptions& options);

}  // namespace deixis::eval
