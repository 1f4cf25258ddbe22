#pragma once
// Shared by tests of error messages: the deixis::Error message a call throws.

#include <string>

#include "core/error.h"

namespace deixis::testing {

// Runs `f` and returns the deixis::Error message it throws ("" when it throws none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace deixis::testing
