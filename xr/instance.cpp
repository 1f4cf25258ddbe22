#include "xr/instance.h"

#include <openxr/openxr_reflection.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "core/error.h"
#include "xr/xr_struct.h"

namespace deixis::xr {

namespace {

std::vector<std::string> offered_extensions(XrInstance none) {
  std::uint32_t count = 0;
  XR_CHECK(none, xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr));
  std::vector<XrExtensionProperties> props(
      count, make<XrExtensionProperties>(XR_TYPE_EXTENSION_PROPERTIES));
  XR_CHECK(none, xrEnumerateInstanceExtensionProperties(nullptr, count, &count, props.data()));
  std::vector<std::string> names;
  for (std::uint32_t i = 0; i < count; ++i) {
    names.emplace_back(props[i].extensionName);
  }
  return names;
}

bool has(const std::vector<std::string>& names, const char* name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

std::string result_string(XrInstance instance, XrResult result) {
  char text[XR_MAX_RESULT_STRING_SIZE] = {};
  if (instance != XR_NULL_HANDLE && XR_SUCCEEDED(xrResultToString(instance, result, text))) {
    return text;
  }
  switch (result) {  // before an instance exists (e.g. no runtime): the spec's names
#define DEIXIS_XR_RESULT_NAME(name, value) \
  case name:                               \
    return #name;
    XR_LIST_ENUM_XrResult(DEIXIS_XR_RESULT_NAME)
#undef DEIXIS_XR_RESULT_NAME
            default : return "XrResult " +
                      std::to_string(static_cast<int>(result));
  }
}

void throw_result(XrInstance instance, XrResult result, const char* call, const char* file,
                  int line) {
  const char* base = std::strrchr(file, '/');
  throw Error(std::string(call) + " failed: " + result_string(instance, result) + " (" +
              (base != nullptr ? base + 1 : file) + ":" + std::to_string(line) + ")");
}

Instance::Instance(const InstanceOptions& options) {
  const std::vector<std::string> offered = offered_extensions(XR_NULL_HANDLE);
  std::vector<const char*> enable;
  if (options.headless) {
    if (!has(offered, XR_MND_HEADLESS_EXTENSION_NAME)) {
      throw Error("the OpenXR runtime does not offer " XR_MND_HEADLESS_EXTENSION_NAME
                  " (needed for a session without graphics)");
    }
    enable.push_back(XR_MND_HEADLESS_EXTENSION_NAME);
    features_.headless = true;
  } else {
    if (!has(offered, "XR_KHR_opengl_enable")) {
      throw Error(
          "the OpenXR runtime does not offer XR_KHR_opengl_enable (the front end renders with "
          "OpenGL)");
    }
    enable.push_back("XR_KHR_opengl_enable");
    features_.opengl = true;
    // EGL where the runtime offers it (no window, no X server); else the Xlib/GLX binding every
    // Linux OpenGL runtime has (xr/gl_context.h).
    if (has(offered, "XR_MNDX_egl_enable")) {
      enable.push_back("XR_MNDX_egl_enable");
      features_.egl = true;
    }
  }
  const bool hands = options.hand_tracking && has(offered, XR_EXT_HAND_TRACKING_EXTENSION_NAME);
  const bool gaze = options.eye_gaze && has(offered, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
  if (hands) {
    enable.push_back(XR_EXT_HAND_TRACKING_EXTENSION_NAME);
  }
  if (gaze) {
    enable.push_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
  }

  auto ci = make<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
  std::snprintf(ci.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "%s",
                options.application.c_str());
  std::snprintf(ci.applicationInfo.engineName, XR_MAX_ENGINE_NAME_SIZE, "%s", "deixis");
  ci.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
  ci.enabledExtensionCount = static_cast<std::uint32_t>(enable.size());
  ci.enabledExtensionNames = enable.data();
  XR_CHECK(XR_NULL_HANDLE, xrCreateInstance(&ci, &instance_));

  try {
    auto sg = make<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
    sg.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XR_CHECK(instance_, xrGetSystem(instance_, &sg, &system_));

    auto hand_props =
        make<XrSystemHandTrackingPropertiesEXT>(XR_TYPE_SYSTEM_HAND_TRACKING_PROPERTIES_EXT);
    auto gaze_props = make<XrSystemEyeGazeInteractionPropertiesEXT>(
        XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT);
    // One extension structure per query: Debian 12's core validation layer (1.0.20) refuses
    // XrSystemEyeGazeInteractionPropertiesEXT chained after the hand-tracking one.
    auto props = make<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES);
    XR_CHECK(instance_, xrGetSystemProperties(instance_, system_, &props));
    if (hands) {
      auto query = make<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES);
      query.next = &hand_props;
      XR_CHECK(instance_, xrGetSystemProperties(instance_, system_, &query));
    }
    if (gaze) {
      auto query = make<XrSystemProperties>(XR_TYPE_SYSTEM_PROPERTIES);
      query.next = &gaze_props;
      XR_CHECK(instance_, xrGetSystemProperties(instance_, system_, &query));
    }
    features_.hand_tracking = hands && hand_props.supportsHandTracking == XR_TRUE;
    features_.eye_gaze = gaze && gaze_props.supportsEyeGazeInteraction == XR_TRUE;

    auto ip = make<XrInstanceProperties>(XR_TYPE_INSTANCE_PROPERTIES);
    XR_CHECK(instance_, xrGetInstanceProperties(instance_, &ip));
    description_ =
        std::string(ip.runtimeName) + " " + std::to_string(XR_VERSION_MAJOR(ip.runtimeVersion)) +
        "." + std::to_string(XR_VERSION_MINOR(ip.runtimeVersion)) + "." +
        std::to_string(XR_VERSION_PATCH(ip.runtimeVersion)) + ", system " + props.systemName;

    const XrViewConfigurationType type = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    std::uint32_t count = 0;
    XR_CHECK(instance_,
             xrEnumerateViewConfigurationViews(instance_, system_, type, 0, &count, nullptr));
    view_config_.views.assign(count,
                              make<XrViewConfigurationView>(XR_TYPE_VIEW_CONFIGURATION_VIEW));
    XR_CHECK(instance_, xrEnumerateViewConfigurationViews(instance_, system_, type, count, &count,
                                                          view_config_.views.data()));
    view_config_.count = count;
    std::uint32_t modes = 0;
    XR_CHECK(instance_,
             xrEnumerateEnvironmentBlendModes(instance_, system_, type, 0, &modes, nullptr));
    std::vector<XrEnvironmentBlendMode> blend(modes);
    XR_CHECK(instance_, xrEnumerateEnvironmentBlendModes(instance_, system_, type, modes, &modes,
                                                         blend.data()));
    if (modes == 0) {
      throw Error("the OpenXR system offers no environment blend mode");
    }
    blend.resize(modes);
    view_config_.blend_mode = choose_blend_mode(blend, options.blend);
  } catch (...) {
    xrDestroyInstance(instance_);
    throw;
  }
}

Instance::~Instance() {
  if (instance_ != XR_NULL_HANDLE) {
    xrDestroyInstance(instance_);
  }
}

XrPath Instance::path(const char* text) const {
  XrPath p = XR_NULL_PATH;
  XR_CHECK(instance_, xrStringToPath(instance_, text, &p));
  return p;
}

PFN_xrVoidFunction Instance::proc(const char* name) const {
  PFN_xrVoidFunction f = nullptr;
  const XrResult r = xrGetInstanceProcAddr(instance_, name, &f);
  if (XR_FAILED(r) || f == nullptr) {
    throw Error(std::string("xrGetInstanceProcAddr(") + name +
                ") failed: " + result_string(instance_, r));
  }
  return f;
}

}  // namespace deixis::xr
