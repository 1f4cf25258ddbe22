// `deixis parity FIXTURE...`: runs the authors' parity fixtures through our networks and prints
// the largest absolute error per reference tensor. Exit code 0 when every check is within its
// tolerance, 1 when one is over, 2 when a fixture cannot be read.

#include <cstdio>

#include "app/commands.h"
#include "core/error.h"
#include "gesture/parity.h"

namespace deixis::app {

namespace {

void print_report(const ParityReport& report) {
  std::printf("%s\n  network %s, checkpoint %s, %d windows\n", report.fixture.c_str(),
              report.network.c_str(), report.checkpoint.c_str(), report.windows);
  std::printf("  %-18s %12s %11s %8s\n", "tensor", "max |error|", "tolerance", "values");
  for (const ParityCheck& check : report.checks) {
    std::printf("  %-18s %12.3g %11.0e %8zu  %s\n", check.tensor.c_str(), check.max_abs_error,
                check.tolerance, check.values, check.passed() ? "ok" : "OVER TOLERANCE");
  }
}

}  // namespace

int run_parity(const ParityOptions& options) {
  int failed = 0;
  int unreadable = 0;
  for (const auto& fixture : options.fixtures) {
    try {
      const ParityReport report = check_parity(fixture, options.reference_dir);
      print_report(report);
      if (!report.passed()) {
        ++failed;
      }
    } catch (const Error& e) {
      std::fprintf(stderr, "deixis parity: %s\n", e.what());
      ++unreadable;
    }
  }
  const int total = static_cast<int>(options.fixtures.size());
  std::printf("parity: %d of %d fixtures pass", total - failed - unreadable, total);
  if (failed + unreadable > 0) {
    std::printf(" (%d over tolerance, %d unreadable)", failed, unreadable);
  }
  std::printf("\n");
  return unreadable > 0 ? 2 : (failed > 0 ? 1 : 0);
}

}  // namespace deixis::app
