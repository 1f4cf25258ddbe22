// app/crash_report.h: a real fault, an abort and a stack overflow each print the signal and a
// stack naming the function that crashed, and the process still dies of that signal. Each runs
// in a death test's child process.

#include "app/crash_report.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>

// Outside any namespace and exported (the test links with -rdynamic): the names the stack must
// show.
extern "C" __attribute__((noinline)) void deixis_test_writes_through_null() {
  // Both volatile: the compiler can neither see the null nor drop the store.
  volatile int* volatile nowhere = nullptr;
  *nowhere = 1;
}

// Deeper than any stack (the limit is volatile, so the compiler cannot see that it never ends).
volatile int deixis_test_depth_limit = 1 << 30;
extern "C" __attribute__((noinline)) int deixis_test_recurses_forever(int depth) {
  volatile char frame[512];
  frame[0] = static_cast<char>(depth);
  if (depth >= deixis_test_depth_limit) {
    return frame[0];
  }
  return deixis_test_recurses_forever(depth + 1) + frame[0];  // not a tail call
}

namespace deixis::app {
namespace {

class CrashReport : public ::testing::Test {
 protected:
  void SetUp() override {
#if defined(DEIXIS_SANITIZED)
    GTEST_SKIP() << "AddressSanitizer reports crashes in this build; the report is not installed";
#endif
    GTEST_FLAG_SET(death_test_style, "threadsafe");  // the child re-executes: a fresh process
  }
};

TEST_F(CrashReport, AFaultNamesTheSignalTheAddressAndTheFunction) {
  EXPECT_EXIT(
      {
        if (!install_crash_report()) {
          std::exit(3);
        }
        deixis_test_writes_through_null();
      },
      ::testing::KilledBySignal(SIGSEGV),
      "deixis: crashed: SIGSEGV \\(invalid memory access\\) at address 0x0\n"
      "deixis: stack.*deixis_test_writes_through_null");
}

TEST_F(CrashReport, AnAbortIsReportedAndStillAborts) {
  EXPECT_EXIT(
      {
        if (!install_crash_report()) {
          std::exit(3);
        }
        std::abort();
      },
      ::testing::KilledBySignal(SIGABRT), "deixis: crashed: SIGABRT \\(aborted\\)\ndeixis: stack");
}

TEST_F(CrashReport, AStackOverflowIsReportedFromTheAlternateStack) {
  EXPECT_EXIT(
      {
        if (!install_crash_report()) {
          std::exit(3);
        }
        std::exit(deixis_test_recurses_forever(0));
      },
      ::testing::KilledBySignal(SIGSEGV), "deixis: crashed: SIGSEGV.*deixis_test_recurses_forever");
}

TEST_F(CrashReport, WithoutItAFaultSaysNothing) {
  // The control: the text above comes from the report, not from the platform.
  EXPECT_EXIT(deixis_test_writes_through_null(), ::testing::KilledBySignal(SIGSEGV), "^$");
}

}  // namespace
}  // namespace deixis::app
