// LeakSanitizer (ASan builds of `deixis` only): Debian 12's OpenXR loader
// (libopenxr_loader.so.1) keeps about 1.5 KB it allocates in xrCreateInstance after a successful
// xrDestroyInstance, once per instance, so `deixis xr` would exit non-zero under ASan. The
// allocations are the loader's own; suppressing by module keeps every leak in Deixis reported
// (docs/decisions.md §40; the OpenXR test binaries carry the same suppression).

extern "C" const char* __lsan_default_suppressions() {
  return "leak:libopenxr_loader.so\n";
}
