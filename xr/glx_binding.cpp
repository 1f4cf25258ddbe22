#include "xr/glx_binding.h"

#include <EGL/egl.h>  // XR_USE_PLATFORM_EGL is set for this library: its types first
#include <GL/glx.h>

#define XR_USE_PLATFORM_XLIB  // this file alone sees the Xlib binding (glx_binding.h)
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <string>

#include "core/error.h"

namespace deixis::xr {

std::shared_ptr<const void> current_glx_binding() {
  auto binding = std::make_shared<XrGraphicsBindingOpenGLXlibKHR>();
  binding->type = XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR;
  binding->xDisplay = glXGetCurrentDisplay();
  binding->glxContext = glXGetCurrentContext();
  binding->glxDrawable = glXGetCurrentDrawable();
  if (binding->xDisplay == nullptr || binding->glxContext == nullptr) {
    throw Error(
        "the OpenXR runtime offers OpenGL only through Xlib/GLX (no XR_MNDX_egl_enable): a GLX "
        "context must be current on this thread (a window on an X server; is DISPLAY set?)");
  }
  // The context's framebuffer configuration and its visual, as the binding names them.
  int config_id = 0;
  glXQueryContext(binding->xDisplay, binding->glxContext, GLX_FBCONFIG_ID, &config_id);
  const int attributes[] = {GLX_FBCONFIG_ID, config_id, None};
  int found = 0;
  GLXFBConfig* configs =
      glXChooseFBConfig(binding->xDisplay, DefaultScreen(binding->xDisplay), attributes, &found);
  if (configs != nullptr && found > 0) {
    binding->glxFBConfig = configs[0];
    if (XVisualInfo* visual = glXGetVisualFromFBConfig(binding->xDisplay, configs[0])) {
      binding->visualid = static_cast<std::uint32_t>(visual->visualid);
      XFree(visual);
    }
  }
  if (configs != nullptr) {
    XFree(configs);
  }
  return binding;
}

}  // namespace deixis::xr
