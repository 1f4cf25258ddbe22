#include "app/crash_report.h"

#include <execinfo.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace deixis::app {

#if !defined(DEIXIS_SANITIZED)
namespace {

constexpr std::array<int, 5> kFatalSignals = {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
constexpr int kMaxFrames = 64;

// Only async-signal-safe calls from here on: write(2), backtrace_symbols_fd (which writes without
// allocating), raise.
void say(const char* text) noexcept {
  const std::size_t length = std::strlen(text);
  std::size_t written = 0;
  while (written < length) {
    const ssize_t n = ::write(STDERR_FILENO, text + written, length - written);
    if (n <= 0) {
      return;
    }
    written += static_cast<std::size_t>(n);
  }
}

// `value` in hexadecimal into `out` (at least 19 bytes): "0x…", no allocation.
void hex(std::uintptr_t value, char* out) noexcept {
  char digits[2 * sizeof(value)];
  int n = 0;
  do {
    digits[n++] = "0123456789abcdef"[value & 0xf];
    value >>= 4;
  } while (value != 0);
  *out++ = '0';
  *out++ = 'x';
  while (n > 0) {
    *out++ = digits[--n];
  }
  *out = '\0';
}

const char* signal_name(int signal) noexcept {
  switch (signal) {
    case SIGSEGV:
      return "SIGSEGV (invalid memory access)";
    case SIGBUS:
      return "SIGBUS (bus error)";
    case SIGILL:
      return "SIGILL (illegal instruction: built for a CPU this one is not?)";
    case SIGFPE:
      return "SIGFPE (arithmetic fault)";
    case SIGABRT:
      return "SIGABRT (aborted)";
    default:
      return "a fatal signal";
  }
}

bool faults_at_address(int signal) noexcept {
  return signal == SIGSEGV || signal == SIGBUS || signal == SIGILL || signal == SIGFPE;
}

void on_fatal_signal(int signal, siginfo_t* info, void*) {
  say("\ndeixis: crashed: ");
  say(signal_name(signal));
  if (info != nullptr && faults_at_address(signal) && info->si_code > 0) {
    char address[24];
    hex(reinterpret_cast<std::uintptr_t>(info->si_addr), address);
    say(" at address ");
    say(address);
  }
  say("\ndeixis: stack (innermost first; resolve +0x… offsets with addr2line -Cfie <deixis>):\n");
  void* frames[kMaxFrames];
  const int count = ::backtrace(frames, kMaxFrames);
  ::backtrace_symbols_fd(frames, count, STDERR_FILENO);
  // Die of the same signal: SA_RESETHAND put its default action back on entry, so this ends the
  // process as the signal would have (with its core dump, where enabled), not with an exit.
  ::raise(signal);
}

}  // namespace
#endif

bool install_crash_report() noexcept {
#if defined(DEIXIS_SANITIZED)
  return false;
#else
  // backtrace() loads libgcc's unwinder on its first call, which allocates: done now, not in the
  // handler of a crash that may have come from inside malloc.
  void* warm[1];
  ::backtrace(warm, 1);
  // An alternate stack, so a stack overflow can still be reported.
  static std::array<std::byte, 64 * 1024> alternate_stack;
  stack_t stack{};
  stack.ss_sp = alternate_stack.data();
  stack.ss_size = alternate_stack.size();
  if (::sigaltstack(&stack, nullptr) != 0) {
    return false;
  }
  struct sigaction action {};
  action.sa_sigaction = on_fatal_signal;
  action.sa_flags = SA_SIGINFO | SA_ONSTACK | SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int signal : kFatalSignals) {
    if (::sigaction(signal, &action, nullptr) != 0) {
      return false;
    }
  }
  return true;
#endif
}

}  // namespace deixis::app
