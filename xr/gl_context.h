#pragma once
// The OpenGL context `deixis xr` renders in, chosen by what the runtime offers (issue 25, item 3;
// docs/xr.md, "Which binding"): an EGL surfaceless context (render::HeadlessContext) where the
// runtime offers XR_MNDX_egl_enable or the session is headless, else a hidden GLFW window, whose
// context is GLX on X11 — XR_KHR_opengl_enable's Xlib binding, which every Linux OpenGL runtime
// offers. Make it before the session (GlSession binds the context current then).

#include <memory>

#include "render/context.h"
#include "xr/instance.h"

namespace deixis::xr {

// Throws deixis::Error with the context's own reason (no X server for a window, no OpenGL 4.5).
std::unique_ptr<render::Context> make_gl_context(const Instance& instance);

}  // namespace deixis::xr
