#pragma once
// OpenXR input and output structs must carry their XrStructureType (and a null `next`) before a
// call; `make<XrFoo>(XR_TYPE_FOO)` gives one zeroed with its type set.

#include <openxr/openxr.h>

namespace deixis::xr {

template <typename T>
T make(XrStructureType type) {
  T value{};
  value.type = type;
  return value;
}

}  // namespace deixis::xr
