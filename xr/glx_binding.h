#pragma once
// XrGraphicsBindingOpenGLXlibKHR for the GLX context current on this thread (a GLFW window's):
// the binding a runtime without XR_MNDX_egl_enable takes (docs/xr.md, "Which binding"). Kept
// apart from gl_session.cpp because Xlib's and GLX's headers bring macros (None, Status, Success,
// Bool) that the rest of the front end must not see.

#include <memory>

namespace deixis::xr {

// The binding (an XrGraphicsBindingOpenGLXlibKHR, to chain as XrSessionCreateInfo::next) of
// the current GLX context; throws deixis::Error when no GLX context is current.
std::shared_ptr<const void> current_glx_binding();

}  // namespace deixis::xr
