#pragma once
// What tests that call OpenXR directly share: result names, zeroed structures of a type
// (xr/xr_struct.h), and XR_OK (an assertion naming the call and its result).

#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#include <gtest/gtest.h>

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

}  // namespace deixis::xr
