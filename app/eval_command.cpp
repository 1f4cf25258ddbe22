// `deixis eval`: every row of the paper's Tables I–IV and Fig. 5 on the held-out subjects
// (eval/evaluation.h), and with --bvh the translator on recordings of real motion in a section of
// its own (eval/real_motion_eval.h); this file resolves the weight sets, runs them and writes
// tables.md, results.json and fig5.png. Exit codes: 0 done, 2 bad flags or files.

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>

#include "app/commands.h"
#include "core/error.h"
#include "core/io/machine.h"
#include "eval/evaluation.h"
#include "eval/figure.h"
#include "eval/real_motion_eval.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

// "label=DIR" → a weight set; a malformed one is a flag error (exit 2).
eval::WeightSet parse_weight_set(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw Error("--weights " + text +
                ": expected LABEL=DIR, e.g. authors=../shared/reference/weights");
  }
  eval::WeightSet w{text.substr(0, eq), text.substr(eq + 1)};
  if (!fs::is_directory(w.dir)) {
    throw Error("--weights " + text + ": " + w.dir.string() + " is not a directory");
  }
  return w;
}

std::vector<eval::WeightSet> weight_sets(const EvalOptions& o) {
  std::vector<eval::WeightSet> sets;
  for (const std::string& text : o.weights) {
    sets.push_back(parse_weight_set(text));
  }
  if (!sets.empty()) {
    return sets;
  }
  if (!fs::is_directory(o.reference_weights)) {
    throw Error(o.reference_weights.string() +
                ": the authors' weights are not there (set DEIXIS_REFERENCE_DIR or pass "
                "--weights LABEL=DIR)");
  }
  sets.push_back({"authors", o.reference_weights});
  if (fs::exists(o.project_weights / "right/MPNet(MoE)(AC)80.safetensors")) {
    sets.push_back({"deixis", o.project_weights});
  }
  return sets;
}

// `text` as one shell word: as it is when it is plain, else in single quotes.
std::string shell_word(const std::string& text) {
  const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+=:,@%", c) != nullptr;
  });
  if (plain) {
    return text;
  }
  std::string quoted = "'";
  for (const char c : text) {
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return quoted + "'";
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) {
    throw Error(path.string() + ": cannot write");
  }
}

}  // namespace

// Decision 57: the test sets take seconds to make, but `deixis eval` does not make them; it
// names the command that does.
std::string eval_data_problem(const fs::path& dir, const std::string& program) {
  std::error_code error;
  std::string what;
  if (!fs::exists(dir, error)) {
    what = "no such directory";
  } else if (!fs::is_directory(dir, error)) {
    what = "not a directory";
  } else {
    for (const fs::directory_entry& entry : fs::directory_iterator(dir, error)) {
      const std::string name = entry.path().filename().string();
      if (name.starts_with("test_") && name.ends_with(".safetensors")) {
        return {};
      }
    }
    what = "no test_<subject>.safetensors in it";
  }
  return dir.string() + ": " + what +
         ". The evaluation reads the held-out subjects' test sets, which the synthetic capture "
         "writes (about 2 s):\n  " +
         shell_word(program) + " capture generate --sets test -o " + shell_word(dir.string()) +
         "\nor give --data a directory that has them (docs/eval.md)";
}

namespace {

void progress_line(const std::string& line) {
  std::fprintf(stderr, "deixis eval: %s\n", line.c_str());
}

// The synthetic protocol; nullopt (after saying why) when its test sets are missing.
std::optional<eval::Report> synthetic_report(const EvalOptions& o,
                                             const std::vector<eval::WeightSet>& sets) {
  eval::EvalOptions options;
  options.data_dir = o.data_dir;
  options.subjects = o.subjects;
  options.weights = sets;
  if (const std::string problem = eval_data_problem(o.data_dir, o.program); !problem.empty()) {
    std::fprintf(stderr, "deixis eval: %s\n", problem.c_str());
    return std::nullopt;
  }
  options.encoder_dir = o.encoder_dir;
  options.quick = o.quick;
  options.threads = o.threads;
  options.sampling = o.quick ? eval::quick_sampling() : eval::full_sampling();
  options.command = o.command_line;
  options.progress = progress_line;
  return eval::evaluate(options);
}

}  // namespace

int run_eval(const EvalOptions& o) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const std::vector<eval::WeightSet> sets = weight_sets(o);
    // --bvh alone measures only the recordings (decision 77): no synthetic test set needed.
    const bool synthetic = o.bvh.empty() || o.data_given;
    eval::Report report;
    if (synthetic) {
      std::optional<eval::Report> r = synthetic_report(o, sets);
      if (!r) {
        return 2;
      }
      report = std::move(*r);
    } else {
      report.command = o.command_line;
      report.machine = machine_description();
    }
    if (!o.bvh.empty()) {
      report.real_motion = eval::evaluate_real_motion({o.bvh, sets, progress_line});
      report.wall_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    fs::create_directories(o.out_dir);
    write_text(o.out_dir / "tables.md", eval::markdown(report));
    write_text(o.out_dir / "results.json", eval::json(report));
    if (!report.figure5.empty()) {
      eval::write_figure5(report.figure5, o.out_dir / "fig5.png");
    }
    std::printf("%s", eval::markdown(report).c_str());
    std::fprintf(stderr, "deixis eval: wrote %s/{tables.md,results.json%s} in %.1f s\n",
                 o.out_dir.string().c_str(), report.figure5.empty() ? "" : ",fig5.png",
                 report.wall_seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "deixis eval: %s\n", e.what());
    return 2;
  }
}

}  // namespace deixis::app
