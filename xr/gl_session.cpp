#include "xr/gl_session.h"

#include <EGL/egl.h>
#include "render/gl.h"  // before OpenXR's platform header: the GL types
// XR_USE_PLATFORM_EGL and XR_USE_GRAPHICS_API_OPENGL are set for this library by CMake.
#include <openxr/openxr_platform.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "xr/glx_binding.h"
#include "xr/xr_struct.h"

namespace deixis::xr {

namespace {

// The current EGL context's display, config and context for XrGraphicsBindingEGLMNDX.
XrGraphicsBindingEGLMNDX current_egl_binding() {
  auto binding = make<XrGraphicsBindingEGLMNDX>(XR_TYPE_GRAPHICS_BINDING_EGL_MNDX);
  binding.display = eglGetCurrentDisplay();
  binding.context = eglGetCurrentContext();
  if (binding.display == EGL_NO_DISPLAY || binding.context == EGL_NO_CONTEXT) {
    throw Error("an OpenXR OpenGL session needs an EGL context current on this thread");
  }
  EGLint config_id = 0;
  if (eglQueryContext(binding.display, binding.context, EGL_CONFIG_ID, &config_id) != EGL_TRUE) {
    throw Error("eglQueryContext(EGL_CONFIG_ID) failed: EGL error " +
                std::to_string(eglGetError()));
  }
  const EGLint attributes[] = {EGL_CONFIG_ID, config_id, EGL_NONE};
  EGLint found = 0;
  if (eglChooseConfig(binding.display, attributes, &binding.config, 1, &found) != EGL_TRUE ||
      found != 1) {
    // A context made with EGL_KHR_no_config_context has no config (EGL_CONFIG_ID 0).
    binding.config = nullptr;
  }
  binding.getProcAddress = eglGetProcAddress;
  return binding;
}

XrSpace reference_space(const Instance& instance, XrSession session, XrReferenceSpaceType type) {
  auto ci = make<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
  ci.referenceSpaceType = type;
  ci.poseInReferenceSpace.orientation.w = 1.0f;
  XrSpace space = XR_NULL_HANDLE;
  XR_CHECK(instance.handle(), xrCreateReferenceSpace(session, &ci, &space));
  return space;
}

}  // namespace

GlSession::GlSession(const Instance& instance) : headless_(instance.features().headless) {
  const XrInstance xi = instance.handle();
  auto ci = make<XrSessionCreateInfo>(XR_TYPE_SESSION_CREATE_INFO);
  ci.systemId = instance.system();
  XrGraphicsBindingEGLMNDX binding{};
  std::shared_ptr<const void> glx;  // XrGraphicsBindingOpenGLXlibKHR (xr/glx_binding.h)
  if (!headless_) {
    auto requirements =
        make<XrGraphicsRequirementsOpenGLKHR>(XR_TYPE_GRAPHICS_REQUIREMENTS_OPENGL_KHR);
    const auto get_requirements = instance.function<PFN_xrGetOpenGLGraphicsRequirementsKHR>(
        "xrGetOpenGLGraphicsRequirementsKHR");
    XR_CHECK(xi, get_requirements(xi, instance.system(), &requirements));
    if (instance.features().egl) {
      binding = current_egl_binding();
      ci.next = &binding;
    } else {
      glx = current_glx_binding();
      ci.next = glx.get();
    }
    GLint major = 0;
    GLint minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    const XrVersion have = XR_MAKE_VERSION(major, minor, 0);
    if (have < requirements.minApiVersionSupported) {
      throw Error("the OpenXR runtime needs OpenGL " +
                  std::to_string(XR_VERSION_MAJOR(requirements.minApiVersionSupported)) + "." +
                  std::to_string(XR_VERSION_MINOR(requirements.minApiVersionSupported)) +
                  "; the context has " + std::to_string(major) + "." + std::to_string(minor));
    }
  }
  XR_CHECK(xi, xrCreateSession(xi, &ci, &session_));
  try {
    std::uint32_t count = 0;
    XR_CHECK(xi, xrEnumerateReferenceSpaces(session_, 0, &count, nullptr));
    std::vector<XrReferenceSpaceType> types(count);
    XR_CHECK(xi, xrEnumerateReferenceSpaces(session_, count, &count, types.data()));
    const bool has_stage =
        std::find(types.begin(), types.end(), XR_REFERENCE_SPACE_TYPE_STAGE) != types.end();
    stage_ =
        reference_space(instance, session_,
                        has_stage ? XR_REFERENCE_SPACE_TYPE_STAGE : XR_REFERENCE_SPACE_TYPE_LOCAL);
    view_ = reference_space(instance, session_, XR_REFERENCE_SPACE_TYPE_VIEW);
  } catch (...) {
    if (stage_ != XR_NULL_HANDLE) {
      xrDestroySpace(stage_);
    }
    xrDestroySession(session_);
    throw;
  }
}

GlSession::~GlSession() {
  if (view_ != XR_NULL_HANDLE) {
    xrDestroySpace(view_);
  }
  if (stage_ != XR_NULL_HANDLE) {
    xrDestroySpace(stage_);
  }
  xrDestroySession(session_);
}

}  // namespace deixis::xr
