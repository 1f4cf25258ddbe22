#pragma once
// What a crashed `deixis` says before it dies (docs/decisions.md §93): on SIGSEGV, SIGBUS,
// SIGILL, SIGFPE or SIGABRT it writes to stderr the signal, the faulting address and the stack
// (glibc's backtrace, function names where the executable exports them, else offsets into it
// for `addr2line -Cfie <deixis> <offset>`), then dies of the same signal, so exit statuses and
// core dumps stay what they would have been. A crash in a test's child process or on a user's
// machine is then located from its log alone.
//
// Not installed in sanitizer builds (DEIXIS_SANITIZED): AddressSanitizer's own report says more.

namespace deixis::app {

// Installs the handlers (idempotent); returns whether they are installed.
bool install_crash_report() noexcept;

}  // namespace deixis::app
