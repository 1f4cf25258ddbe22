// Instance, system, view configuration, paths and events.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include <openxr/openxr_reflection.h>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

constexpr XrSystemId kSystem = 1;
constexpr std::uint32_t kViewSize = 512;  // recommended per eye (llvmpipe renders it in time)

const char* const kExtensions[] = {"XR_KHR_opengl_enable", "XR_MNDX_egl_enable", "XR_MND_headless",
                                   "XR_EXT_hand_tracking", "XR_EXT_eye_gaze_interaction"};

// Extensions hidden by DEIXIS_XR_HIDE_EXTENSIONS (comma-separated), so tests can take the
// controller path or the one without eye gaze.
bool hidden(const char* name) {
  const char* env = std::getenv("DEIXIS_XR_HIDE_EXTENSIONS");
  if (env == nullptr) {
    return false;
  }
  std::stringstream list(env);
  std::string item;
  while (std::getline(list, item, ',')) {
    if (item == name) {
      return true;
    }
  }
  return false;
}

bool offered(const char* name) {
  for (const char* e : kExtensions) {
    if (std::strcmp(e, name) == 0) {
      return !hidden(e);
    }
  }
  return false;
}

bool valid_instance(XrInstance instance) {
  const Runtime& rt = state();
  return rt.instance_live && from_handle(instance) == rt.instance;
}

void reset(Runtime& rt) {
  rt.instance_live = false;
  rt.enabled_extensions.clear();
  rt.graphics_requirements_queried = false;
  rt.system_queried = false;
  rt.instance = 0;
  rt.session = 0;
  rt.session_state = {};
  rt.spaces.clear();
  rt.swapchains.clear();
  rt.action_sets.clear();
  rt.actions.clear();
  rt.hand_trackers.clear();
  rt.paths.clear();
  rt.suggested.clear();
  rt.events.clear();
  rt.script = default_script();
  rt.record = {};
  rt.record_path.clear();
}

// The checks every system-level call starts with: a live instance, our one system.
XrResult check_system(XrInstance instance, XrSystemId system) {
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  return system == kSystem ? XR_SUCCESS : XR_ERROR_SYSTEM_INVALID;
}

// The same, and the one view configuration the runtime has (primary stereo).
XrResult check_view_configuration(XrInstance instance, XrSystemId system,
                                  XrViewConfigurationType type) {
  if (const XrResult r = check_system(instance, system); r != XR_SUCCESS) {
    return r;
  }
  return type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO
             ? XR_SUCCESS
             : XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
}

}  // namespace

XrResult XRAPI_CALL EnumerateInstanceExtensionProperties(const char* layer, uint32_t capacity,
                                                         uint32_t* count,
                                                         XrExtensionProperties* out) {
  if (layer != nullptr) {
    return XR_ERROR_API_LAYER_NOT_PRESENT;
  }
  XrExtensionProperties values[std::size(kExtensions)];
  uint32_t n = 0;
  for (const char* e : kExtensions) {
    if (hidden(e)) {
      continue;
    }
    XrExtensionProperties& p = values[n++];
    p = {XR_TYPE_EXTENSION_PROPERTIES, nullptr, {}, 1};
    std::snprintf(p.extensionName, sizeof(p.extensionName), "%s", e);
  }
  if (out != nullptr) {
    for (uint32_t i = 0; i < std::min(capacity, n); ++i) {
      if (out[i].type != XR_TYPE_EXTENSION_PROPERTIES) {
        return XR_ERROR_VALIDATION_FAILURE;
      }
    }
  }
  return two_call(capacity, count, out, values, n);
}

XrResult XRAPI_CALL EnumerateApiLayerProperties(uint32_t, uint32_t* count, XrApiLayerProperties*) {
  if (count == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  *count = 0;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL CreateInstance(const XrInstanceCreateInfo* info, XrInstance* instance) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (info == nullptr || instance == nullptr || info->type != XR_TYPE_INSTANCE_CREATE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (XR_VERSION_MAJOR(info->applicationInfo.apiVersion) != 1) {
    return XR_ERROR_API_VERSION_UNSUPPORTED;
  }
  if (rt.instance_live) {
    return XR_ERROR_LIMIT_REACHED;  // one instance at a time
  }
  std::vector<std::string> enabled;
  for (uint32_t i = 0; i < info->enabledExtensionCount; ++i) {
    const char* name = info->enabledExtensionNames[i];
    if (name == nullptr || !offered(name)) {
      return XR_ERROR_EXTENSION_NOT_PRESENT;
    }
    enabled.emplace_back(name);
  }
  Script script = default_script();
  if (const char* path = std::getenv("DEIXIS_XR_SCRIPT"); path != nullptr && *path != '\0') {
    std::string error;
    std::optional<Script> loaded = load_script(path, error);
    if (!loaded) {
      std::fprintf(stderr, "deixis xr test runtime: DEIXIS_XR_SCRIPT=%s\n", error.c_str());
      return XR_ERROR_INITIALIZATION_FAILED;
    }
    script = std::move(*loaded);
  }
  reset(rt);
  rt.script = std::move(script);
  if (const char* path = std::getenv("DEIXIS_XR_RECORD"); path != nullptr) {
    rt.record_path = path;
  }
  rt.enabled_extensions = std::move(enabled);
  rt.instance = rt.new_handle();
  rt.instance_live = true;
  *instance = to_handle<XrInstance>(rt.instance);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroyInstance(XrInstance instance) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (!rt.record_path.empty() && !rt.record.write(rt.record_path)) {
    std::fprintf(stderr, "deixis xr test runtime: cannot write DEIXIS_XR_RECORD=%s\n",
                 rt.record_path.c_str());
  }
  reset(rt);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetInstanceProperties(XrInstance instance, XrInstanceProperties* props) {
  std::lock_guard lock(state().mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (props == nullptr || props->type != XR_TYPE_INSTANCE_PROPERTIES) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  props->runtimeVersion = XR_MAKE_VERSION(0, 1, 0);
  std::snprintf(props->runtimeName, sizeof(props->runtimeName), "%s",
                "Deixis test runtime (scripted)");
  return XR_SUCCESS;
}

XrResult XRAPI_CALL PollEvent(XrInstance instance, XrEventDataBuffer* event) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (event == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (rt.events.empty()) {
    return XR_EVENT_UNAVAILABLE;
  }
  *event = rt.events.front();
  rt.events.pop_front();
  return XR_SUCCESS;
}

XrResult XRAPI_CALL ResultToString(XrInstance instance, XrResult value,
                                   char buffer[XR_MAX_RESULT_STRING_SIZE]) {
  std::lock_guard lock(state().mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  std::snprintf(buffer, XR_MAX_RESULT_STRING_SIZE, "%s", result_name(value));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL StructureTypeToString(XrInstance instance, XrStructureType value,
                                          char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
  std::lock_guard lock(state().mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  const char* name = nullptr;
  switch (value) {
#define DEIXIS_XRT_STRUCTURE_CASE(n, v) \
  case n:                               \
    name = #n;                          \
    break;
    XR_LIST_ENUM_XrStructureType(DEIXIS_XRT_STRUCTURE_CASE)
#undef DEIXIS_XRT_STRUCTURE_CASE
        default : break;
  }
  if (name != nullptr) {
    std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "%s", name);
  } else {
    std::snprintf(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_%d",
                  static_cast<int>(value));
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetSystem(XrInstance instance, const XrSystemGetInfo* info, XrSystemId* id) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || id == nullptr || info->type != XR_TYPE_SYSTEM_GET_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  if (info->formFactor != XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY) {
    return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
  }
  rt.system_queried = true;
  *id = kSystem;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL GetSystemProperties(XrInstance instance, XrSystemId system,
                                        XrSystemProperties* props) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check_system(instance, system); r != XR_SUCCESS) {
    return r;
  }
  if (props == nullptr || props->type != XR_TYPE_SYSTEM_PROPERTIES) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  props->systemId = kSystem;
  props->vendorId = 0;
  std::snprintf(props->systemName, sizeof(props->systemName), "%s", "Deixis scripted headset");
  props->graphicsProperties = {2048, 2048, 16};
  props->trackingProperties = {XR_TRUE, XR_TRUE};
  for (auto* next = static_cast<XrBaseOutStructure*>(props->next); next != nullptr;
       next = next->next) {
    if (next->type == XR_TYPE_SYSTEM_HAND_TRACKING_PROPERTIES_EXT) {
      reinterpret_cast<XrSystemHandTrackingPropertiesEXT*>(next)->supportsHandTracking =
          rt.extension_enabled("XR_EXT_hand_tracking") ? XR_TRUE : XR_FALSE;
    } else if (next->type == XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT) {
      reinterpret_cast<XrSystemEyeGazeInteractionPropertiesEXT*>(next)->supportsEyeGazeInteraction =
          rt.extension_enabled("XR_EXT_eye_gaze_interaction") ? XR_TRUE : XR_FALSE;
    }
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL EnumerateViewConfigurations(XrInstance instance, XrSystemId system,
                                                uint32_t capacity, uint32_t* count,
                                                XrViewConfigurationType* out) {
  std::lock_guard lock(state().mutex);
  if (const XrResult r = check_system(instance, system); r != XR_SUCCESS) {
    return r;
  }
  const XrViewConfigurationType values[] = {XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO};
  return two_call(capacity, count, out, values, 1);
}

XrResult XRAPI_CALL GetViewConfigurationProperties(XrInstance instance, XrSystemId system,
                                                   XrViewConfigurationType type,
                                                   XrViewConfigurationProperties* props) {
  std::lock_guard lock(state().mutex);
  if (const XrResult r = check_view_configuration(instance, system, type); r != XR_SUCCESS) {
    return r;
  }
  if (props == nullptr || props->type != XR_TYPE_VIEW_CONFIGURATION_PROPERTIES) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  props->viewConfigurationType = type;
  props->fovMutable = XR_FALSE;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL EnumerateViewConfigurationViews(XrInstance instance, XrSystemId system,
                                                    XrViewConfigurationType type, uint32_t capacity,
                                                    uint32_t* count, XrViewConfigurationView* out) {
  std::lock_guard lock(state().mutex);
  if (const XrResult r = check_view_configuration(instance, system, type); r != XR_SUCCESS) {
    return r;
  }
  const XrViewConfigurationView v{
      XR_TYPE_VIEW_CONFIGURATION_VIEW, nullptr, kViewSize, 2048, kViewSize, 2048, 1, 1};
  const XrViewConfigurationView values[] = {v, v};
  return two_call(capacity, count, out, values, 2);
}

XrResult XRAPI_CALL EnumerateEnvironmentBlendModes(XrInstance instance, XrSystemId system,
                                                   XrViewConfigurationType type, uint32_t capacity,
                                                   uint32_t* count, XrEnvironmentBlendMode* out) {
  const Runtime& rt = state();
  std::lock_guard lock(state().mutex);
  if (const XrResult r = check_view_configuration(instance, system, type); r != XR_SUCCESS) {
    return r;
  }
  // The script's headset offers these, in its order (default: opaque alone).
  const std::vector<XrEnvironmentBlendMode>& modes = rt.script.blend_modes;
  return two_call(capacity, count, out, modes.data(), static_cast<uint32_t>(modes.size()));
}

XrResult XRAPI_CALL StringToPath(XrInstance instance, const char* string, XrPath* path) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (string == nullptr || path == nullptr || string[0] != '/' ||
      std::strlen(string) >= XR_MAX_PATH_LENGTH) {
    return XR_ERROR_PATH_FORMAT_INVALID;
  }
  *path = rt.intern(string);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL PathToString(XrInstance instance, XrPath path, uint32_t capacity,
                                 uint32_t* count, char* buffer) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_instance(instance)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (path == XR_NULL_PATH || path > rt.paths.size()) {
    return XR_ERROR_PATH_INVALID;
  }
  const std::string& s = rt.paths[path - 1];
  return two_call(capacity, count, buffer, s.c_str(), static_cast<uint32_t>(s.size() + 1));
}

XrResult XRAPI_CALL GetOpenGLGraphicsRequirementsKHR(XrInstance instance, XrSystemId system,
                                                     XrGraphicsRequirementsOpenGLKHR* req) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (const XrResult r = check_system(instance, system); r != XR_SUCCESS) {
    return r;
  }
  if (req == nullptr || req->type != XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  req->minApiVersionSupported = XR_MAKE_VERSION(4, 5, 0);
  req->maxApiVersionSupported = XR_MAKE_VERSION(4, 6, 0);
  rt.graphics_requirements_queried = true;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
