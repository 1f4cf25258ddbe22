// The two symbols the loader looks up in the runtime library: xrNegotiateLoaderRuntimeInterface
// (exported) and the xrGetInstanceProcAddr it hands back, which finds functions by name.

#include <cstring>
#include <iterator>

#include "xr_test_runtime/api.h"
#include "xr_test_runtime/loader_abi.h"
#include "xr_test_runtime/runtime.h"

namespace deixis::xrt {
namespace {

struct Entry {
  const char* name;
  PFN_xrVoidFunction function;
  bool without_instance;  // may be fetched with XR_NULL_HANDLE
  const char* extension;  // must be enabled, or nullptr
};

template <typename F>
PFN_xrVoidFunction fn(F f) {
  return reinterpret_cast<PFN_xrVoidFunction>(f);
}

XrResult XRAPI_CALL GetInstanceProcAddr(XrInstance instance, const char* name,
                                        PFN_xrVoidFunction* function);

const Entry kEntries[] = {
    {"xrGetInstanceProcAddr", fn(GetInstanceProcAddr), true, nullptr},
    {"xrEnumerateInstanceExtensionProperties", fn(EnumerateInstanceExtensionProperties), true,
     nullptr},
    {"xrEnumerateApiLayerProperties", fn(EnumerateApiLayerProperties), true, nullptr},
    {"xrCreateInstance", fn(CreateInstance), true, nullptr},
    {"xrDestroyInstance", fn(DestroyInstance), false, nullptr},
    {"xrGetInstanceProperties", fn(GetInstanceProperties), false, nullptr},
    {"xrPollEvent", fn(PollEvent), false, nullptr},
    {"xrResultToString", fn(ResultToString), false, nullptr},
    {"xrStructureTypeToString", fn(StructureTypeToString), false, nullptr},
    {"xrGetSystem", fn(GetSystem), false, nullptr},
    {"xrGetSystemProperties", fn(GetSystemProperties), false, nullptr},
    {"xrEnumerateViewConfigurations", fn(EnumerateViewConfigurations), false, nullptr},
    {"xrGetViewConfigurationProperties", fn(GetViewConfigurationProperties), false, nullptr},
    {"xrEnumerateViewConfigurationViews", fn(EnumerateViewConfigurationViews), false, nullptr},
    {"xrEnumerateEnvironmentBlendModes", fn(EnumerateEnvironmentBlendModes), false, nullptr},
    {"xrStringToPath", fn(StringToPath), false, nullptr},
    {"xrPathToString", fn(PathToString), false, nullptr},
    {"xrGetOpenGLGraphicsRequirementsKHR", fn(GetOpenGLGraphicsRequirementsKHR), false,
     "XR_KHR_opengl_enable"},
    {"xrCreateSession", fn(CreateSession), false, nullptr},
    {"xrDestroySession", fn(DestroySession), false, nullptr},
    {"xrBeginSession", fn(BeginSession), false, nullptr},
    {"xrEndSession", fn(EndSession), false, nullptr},
    {"xrRequestExitSession", fn(RequestExitSession), false, nullptr},
    {"xrWaitFrame", fn(WaitFrame), false, nullptr},
    {"xrBeginFrame", fn(BeginFrame), false, nullptr},
    {"xrEndFrame", fn(EndFrame), false, nullptr},
    {"xrEnumerateReferenceSpaces", fn(EnumerateReferenceSpaces), false, nullptr},
    {"xrCreateReferenceSpace", fn(CreateReferenceSpace), false, nullptr},
    {"xrCreateActionSpace", fn(CreateActionSpace), false, nullptr},
    {"xrDestroySpace", fn(DestroySpace), false, nullptr},
    {"xrGetReferenceSpaceBoundsRect", fn(GetReferenceSpaceBoundsRect), false, nullptr},
    {"xrLocateSpace", fn(LocateSpace), false, nullptr},
    {"xrLocateViews", fn(LocateViews), false, nullptr},
    {"xrEnumerateSwapchainFormats", fn(EnumerateSwapchainFormats), false, nullptr},
    {"xrCreateSwapchain", fn(CreateSwapchain), false, nullptr},
    {"xrDestroySwapchain", fn(DestroySwapchain), false, nullptr},
    {"xrEnumerateSwapchainImages", fn(EnumerateSwapchainImages), false, nullptr},
    {"xrAcquireSwapchainImage", fn(AcquireSwapchainImage), false, nullptr},
    {"xrWaitSwapchainImage", fn(WaitSwapchainImage), false, nullptr},
    {"xrReleaseSwapchainImage", fn(ReleaseSwapchainImage), false, nullptr},
    {"xrCreateActionSet", fn(CreateActionSet), false, nullptr},
    {"xrDestroyActionSet", fn(DestroyActionSet), false, nullptr},
    {"xrCreateAction", fn(CreateAction), false, nullptr},
    {"xrDestroyAction", fn(DestroyAction), false, nullptr},
    {"xrSuggestInteractionProfileBindings", fn(SuggestInteractionProfileBindings), false, nullptr},
    {"xrAttachSessionActionSets", fn(AttachSessionActionSets), false, nullptr},
    {"xrSyncActions", fn(SyncActions), false, nullptr},
    {"xrGetActionStateBoolean", fn(GetActionStateBoolean), false, nullptr},
    {"xrGetActionStateFloat", fn(GetActionStateFloat), false, nullptr},
    {"xrGetActionStateVector2f", fn(GetActionStateVector2f), false, nullptr},
    {"xrGetActionStatePose", fn(GetActionStatePose), false, nullptr},
    {"xrGetCurrentInteractionProfile", fn(GetCurrentInteractionProfile), false, nullptr},
    {"xrEnumerateBoundSourcesForAction", fn(EnumerateBoundSourcesForAction), false, nullptr},
    {"xrGetInputSourceLocalizedName", fn(GetInputSourceLocalizedName), false, nullptr},
    {"xrApplyHapticFeedback", fn(ApplyHapticFeedback), false, nullptr},
    {"xrStopHapticFeedback", fn(StopHapticFeedback), false, nullptr},
    {"xrCreateHandTrackerEXT", fn(CreateHandTrackerEXT), false, "XR_EXT_hand_tracking"},
    {"xrDestroyHandTrackerEXT", fn(DestroyHandTrackerEXT), false, "XR_EXT_hand_tracking"},
    {"xrLocateHandJointsEXT", fn(LocateHandJointsEXT), false, "XR_EXT_hand_tracking"},
};

XrResult XRAPI_CALL GetInstanceProcAddr(XrInstance instance, const char* name,
                                        PFN_xrVoidFunction* function) {
  if (name == nullptr || function == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  *function = nullptr;
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const bool live = instance != XR_NULL_HANDLE;
  if (live && (!rt.instance_live || from_handle(instance) != rt.instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  for (const Entry& e : kEntries) {
    if (std::strcmp(e.name, name) != 0) {
      continue;
    }
    if (!live && !e.without_instance) {
      return XR_ERROR_HANDLE_INVALID;
    }
    if (e.extension != nullptr && !rt.extension_enabled(e.extension)) {
      return XR_ERROR_FUNCTION_UNSUPPORTED;
    }
    *function = e.function;
    return XR_SUCCESS;
  }
  return XR_ERROR_FUNCTION_UNSUPPORTED;
}

}  // namespace
}  // namespace deixis::xrt

extern "C" __attribute__((visibility("default"))) XrResult XRAPI_CALL
xrNegotiateLoaderRuntimeInterface(const deixis::xrt::NegotiateLoaderInfo* info,
                                  deixis::xrt::NegotiateRuntimeRequest* request) {
  using namespace deixis::xrt;
  if (info == nullptr || request == nullptr || info->structType != kLoaderInfoStruct ||
      info->structVersion != kLoaderInfoStructVersion ||
      info->structSize != sizeof(NegotiateLoaderInfo) ||
      request->structType != kRuntimeRequestStruct ||
      request->structVersion != kRuntimeInfoStructVersion ||
      request->structSize != sizeof(NegotiateRuntimeRequest) ||
      info->minInterfaceVersion > kLoaderRuntimeInterfaceVersion ||
      info->maxInterfaceVersion < kLoaderRuntimeInterfaceVersion ||
      info->minApiVersion > XR_CURRENT_API_VERSION || XR_VERSION_MAJOR(info->maxApiVersion) < 1) {
    return XR_ERROR_INITIALIZATION_FAILED;
  }
  request->runtimeInterfaceVersion = kLoaderRuntimeInterfaceVersion;
  request->runtimeApiVersion = XR_CURRENT_API_VERSION;
  request->getInstanceProcAddr = GetInstanceProcAddr;
  return XR_SUCCESS;
}
