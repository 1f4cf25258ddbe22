#pragma once
// The loader ↔ runtime negotiation ABI (OpenXR loader documentation, "Runtime Interface
// Negotiation"). Debian's libopenxr-dev does not install the SDK's loader_interfaces.h, so the two
// structures and the constants the runtime needs are declared here as the loader defines them.

#include <openxr/openxr.h>

#include <cstddef>
#include <cstdint>

namespace deixis::xrt {

inline constexpr std::int32_t kLoaderInfoStruct = 1;      // XR_LOADER_INTERFACE_STRUCT_LOADER_INFO
inline constexpr std::int32_t kRuntimeRequestStruct = 3;  // ..._RUNTIME_REQUEST
inline constexpr std::uint32_t kLoaderInfoStructVersion = 1;
inline constexpr std::uint32_t kRuntimeInfoStructVersion = 1;
inline constexpr std::uint32_t kLoaderRuntimeInterfaceVersion = 1;

struct NegotiateLoaderInfo {
  std::int32_t structType;
  std::uint32_t structVersion;
  std::size_t structSize;
  std::uint32_t minInterfaceVersion;
  std::uint32_t maxInterfaceVersion;
  XrVersion minApiVersion;
  XrVersion maxApiVersion;
};

struct NegotiateRuntimeRequest {
  std::int32_t structType;
  std::uint32_t structVersion;
  std::size_t structSize;
  std::uint32_t runtimeInterfaceVersion;
  XrVersion runtimeApiVersion;
  PFN_xrGetInstanceProcAddr getInstanceProcAddr;
};

}  // namespace deixis::xrt
