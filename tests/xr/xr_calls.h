#pragma once
// What tests that call OpenXR directly share: result names, zeroed structures of a type
// (xr/xr_struct.h), and XR_OK (an assertion naming the call and its result).

#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "xr/xr_struct.h"  // make<XrFoo>(XR_TYPE_FOO)

namespace deixis::xr {

inline const char* name(XrResult r) {
  switch (r) {
#define DEIXIS_TEST_RESULT(n, v) \
  case n:                        \
    return #n;
    XR_LIST_ENUM_XrResult(DEIXIS_TEST_RESULT)
#undef DEIXIS_TEST_RESULT
        default : return "XR_UNKNOWN_RESULT";
  }
}

#define XR_OK(call)                                                                  \
  do {                                                                               \
    const XrResult r_ = (call);                                                      \
    ASSERT_TRUE(XR_SUCCEEDED(r_)) << #call << " failed: " << ::deixis::xr::name(r_); \
  } while (false)

// What `call` writes to standard error (the runtime says there why it refuses a script), caught
// in `file`, with the call's result.
template <typename Call>
std::pair<XrResult, std::string> with_stderr(const std::filesystem::path& file, Call&& call) {
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  const int fd = open(file.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
  dup2(fd, STDERR_FILENO);
  const XrResult r = call();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  close(fd);
  std::ifstream in(file);
  std::stringstream said;
  said << in.rdbuf();
  return {r, said.str()};
}

}  // namespace deixis::xr
