// Sanitizer runtime options and leak suppressions compiled into every executable of an ASan build
// (DEIXIS_SANITIZE; the top-level CMakeLists.txt adds this file to executables only), so a test,
// `deixis` or a test's child process runs with them however it is started: from ctest, by hand
// or by a test.
//
// intercept_tls_get_addr=0: GCC 12's sanitizer runtime (fixed upstream after GCC 13 / LLVM 16)
// takes a dynamic TLS block whose start lies 16 bytes into a page for a pre-2.25 glibc block
// header and reads the two words before it as that block's bounds. Debian 12's glibc 2.36 has no
// such header, so when a malloc'd block lands on that offset by chance, LeakSanitizer's
// stop-the-world tracer dereferences garbage at exit ("Tracer caught signal 11 ... LeakSanitizer
// has encountered a fatal error"): a test that passed ends aborted with no leak reported. It
// struck HeadlessRenderTest.LabelsAreDrawnAboveTheirObjects in CI (Mesa's threads use dynamic
// TLS). Without the interceptor, LSan still scans every thread's static TLS and stack, and the
// dynamic TLS blocks are ordinary heap blocks it scans as such (docs/decisions.md §49).

extern "C" const char* __asan_default_options() {
  return "intercept_tls_get_addr=0";
}

// LeakSanitizer: Debian 12's OpenXR loader (libopenxr_loader.so.1) keeps about 1.5 KB it allocates
// in xrCreateInstance after a successful xrDestroyInstance, once per instance, so `deixis xr` and
// the OpenXR tests would exit non-zero. The allocations are the loader's own; suppressing by
// module keeps every leak in Deixis and its test runtime reported (docs/decisions.md §40), and
// executables that never load the loader are unaffected.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libopenxr_loader.so\n";
}
