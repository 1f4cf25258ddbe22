// The main() of every Deixis benchmark executable. Runs Google Benchmark with repetitions (10 by
// default) and, besides Google Benchmark's own console output, prints a Markdown table of
// mean ± std per benchmark with the commit, CPU and compiler flags, so that a figure pasted into
// README.md says where it came from. `--benchmark_format=json` and the other Google Benchmark
// flags still work.

#include <benchmark/benchmark.h>

#include <array>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/io/machine.h"

namespace {

std::string command_output(const std::string& command) {
  std::array<char, 256> buffer{};
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) {
    return "unknown";
  }
  while (fgets(buffer.data(), buffer.size(), pipe.get()) != nullptr) {
    out += buffer.data();
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) {
    out.pop_back();
  }
  return out.empty() ? "unknown" : out;
}

// Collects the mean and stddev aggregates and prints them as Markdown at the end.
class MarkdownReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Aggregate) {
        continue;
      }
      Row& row = rows_[run.run_name.str()];
      if (row.order == 0) {
        row.order = ++count_;
      }
      const double us =
          run.GetAdjustedRealTime() * (run.time_unit == benchmark::kNanosecond    ? 1e-3
                                       : run.time_unit == benchmark::kMicrosecond ? 1.0
                                       : run.time_unit == benchmark::kMillisecond ? 1e3
                                                                                  : 1e6);
      if (run.aggregate_name == "mean") {
        row.mean_us = us;
        row.repetitions = run.repetitions;
      } else if (run.aggregate_name == "stddev") {
        row.std_us = us;
      }
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    std::vector<std::pair<std::string, Row>> ordered(rows_.begin(), rows_.end());
    std::sort(ordered.begin(), ordered.end(),
              [](const auto& a, const auto& b) { return a.second.order < b.second.order; });
    std::printf("\ncommit %s, CPU %s, one thread\nflags: %s\n\n",
                command_output("git -C " DEIXIS_SOURCE_DIR " describe --always --dirty 2>/dev/null")
                    .c_str(),
                deixis::cpu_model().c_str(), DEIXIS_BENCH_FLAGS);
    std::printf("| benchmark | mean (µs) | std (µs) | repetitions |\n|---|---:|---:|---:|\n");
    for (const auto& [name, row] : ordered) {
      std::printf("| %s | %.2f | %.2f | %lld |\n", name.c_str(), row.mean_us, row.std_us,
                  static_cast<long long>(row.repetitions));
    }
  }

 private:
  struct Row {
    int order = 0;
    double mean_us = 0;
    double std_us = 0;
    std::int64_t repetitions = 0;
  };
  std::map<std::string, Row> rows_;
  int count_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  // Defaults that make every run a figure with a spread; explicit flags override them.
  std::vector<char*> args(argv, argv + argc);
  std::string repetitions = "--benchmark_repetitions=10";
  std::string aggregates = "--benchmark_report_aggregates_only=true";
  bool has_repetitions = false;
  bool machine_format = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    has_repetitions |= arg.rfind("--benchmark_repetitions", 0) == 0;
    machine_format |=
        arg.rfind("--benchmark_format", 0) == 0 && arg != "--benchmark_format=console";
  }
  if (!has_repetitions) {
    args.insert(args.begin() + 1, repetitions.data());
    args.insert(args.begin() + 2, aggregates.data());
  }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) {
    return 1;
  }
  if (machine_format) {
    benchmark::RunSpecifiedBenchmarks();
  } else {
    MarkdownReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
  }
  benchmark::Shutdown();
  return 0;
}
