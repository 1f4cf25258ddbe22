#pragma once
// The OpenXR instance and the head-mounted system: which extensions the runtime offers and which
// the front end enables (OpenGL, with XR_MNDX_egl_enable where offered, else the Xlib/GLX binding;
// or XR_MND_headless; hand tracking and eye gaze where offered), and the system's view
// configuration. Every failing call throws
// deixis::Error naming the call, its XrResult (xrResultToString) and where it was made.

#include <openxr/openxr.h>

#include <cstdint>
#include <string>
#include <vector>

#include "xr/blend_mode.h"

namespace deixis::xr {

// XR_CHECK(instance, call): throws deixis::Error "xrFoo(...) failed: XR_ERROR_... (file:line)"
// unless the call succeeds (XR_SUCCEEDED; qualified successes such as XR_SESSION_LOSS_PENDING are
// the caller's to read).
[[noreturn]] void throw_result(XrInstance instance, XrResult result, const char* call,
                               const char* file, int line);
#define XR_CHECK(instance, call)                                                            \
  do {                                                                                      \
    const XrResult deixis_xr_result_ = (call);                                              \
    if (XR_FAILED(deixis_xr_result_)) {                                                     \
      ::deixis::xr::throw_result((instance), deixis_xr_result_, #call, __FILE__, __LINE__); \
    }                                                                                       \
  } while (false)

// "XR_ERROR_SESSION_NOT_RUNNING" (the runtime's xrResultToString, or the number without an
// instance).
std::string result_string(XrInstance instance, XrResult result);

struct InstanceOptions {
  bool headless = false;      // XR_MND_headless: no graphics binding, no swapchains
  bool hand_tracking = true;  // XR_EXT_hand_tracking where offered (else controller poses)
  bool eye_gaze = true;       // XR_EXT_eye_gaze_interaction where offered
  std::string application = "deixis";
  BlendChoice blend = BlendChoice::kAuto;  // which environment blend mode (xr/blend_mode.h)
};

// What the instance enabled and the system supports.
struct Features {
  bool opengl = false;         // XR_KHR_opengl_enable
  bool egl = false;            // XR_MNDX_egl_enable (else the Xlib/GLX binding)
  bool headless = false;       // XR_MND_headless
  bool hand_tracking = false;  // extension enabled and the system supports it
  bool eye_gaze = false;       // extension enabled and the system supports it
};

struct ViewConfig {
  std::uint32_t count = 0;
  std::vector<XrViewConfigurationView> views;  // recommended sizes per view
  XrEnvironmentBlendMode blend_mode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;  // the one chosen
};

class Instance {
 public:
  // Creates the instance and gets the head-mounted system. Throws deixis::Error when there is no
  // runtime, the runtime lacks XR_KHR_opengl_enable (or XR_MND_headless when asked for), or any
  // call fails.
  explicit Instance(const InstanceOptions& options);
  ~Instance();
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  XrInstance handle() const { return instance_; }
  XrSystemId system() const { return system_; }
  const Features& features() const { return features_; }
  const ViewConfig& view_config() const { return view_config_; }
  // "Deixis test runtime 0.1.0, system Deixis scripted headset".
  const std::string& description() const { return description_; }

  XrPath path(const char* text) const;
  // An extension function (xrGetInstanceProcAddr); throws when the runtime lacks it.
  template <typename Pfn>
  Pfn function(const char* name) const {
    return reinterpret_cast<Pfn>(proc(name));
  }

 private:
  PFN_xrVoidFunction proc(const char* name) const;

  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  Features features_;
  ViewConfig view_config_;
  std::string description_;
};

}  // namespace deixis::xr
