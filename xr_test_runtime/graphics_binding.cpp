// The X11/GLX and EGL side of the session's graphics binding (graphics_binding.h).
#include "xr_test_runtime/graphics_binding.h"

#include <EGL/egl.h>
#include <GL/glx.h>

// This file alone sees the platform structures (graphics_binding.h says why).
#define XR_USE_PLATFORM_XLIB
#define XR_USE_PLATFORM_EGL
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

namespace deixis::xrt {

namespace {

template <typename F>
bool load(F& f, const char* name, GraphicsBinding binding) {
  const auto* n = reinterpret_cast<const GLubyte*>(name);
  f = binding == GraphicsBinding::kXlib ? reinterpret_cast<F>(glXGetProcAddressARB(n))
                                        : reinterpret_cast<F>(eglGetProcAddress(name));
  return f != nullptr;
}

bool load_gl(GraphicsBinding binding, GlFunctions& gl) {
  return load(gl.GenTextures, "glGenTextures", binding) &&
         load(gl.DeleteTextures, "glDeleteTextures", binding) &&
         load(gl.BindTexture, "glBindTexture", binding) &&
         load(gl.TexStorage2D, "glTexStorage2D", binding) &&
         load(gl.GetTexImage, "glGetTexImage", binding) &&
         load(gl.PixelStorei, "glPixelStorei", binding) && load(gl.GetError, "glGetError", binding);
}

}  // namespace

bool find_graphics_binding(const void* next, bool egl_enabled, SessionGraphics& out,
                           std::string& problem) {
  out = {};
  for (auto* s = static_cast<const XrBaseInStructure*>(next); s != nullptr; s = s->next) {
    if (s->type == XR_TYPE_GRAPHICS_BINDING_OPENGL_XLIB_KHR) {
      const auto* b = reinterpret_cast<const XrGraphicsBindingOpenGLXlibKHR*>(s);
      if (b->xDisplay == nullptr || b->glxContext == nullptr || b->glxDrawable == 0) {
        problem = "XrGraphicsBindingOpenGLXlibKHR without xDisplay, glxContext or glxDrawable";
        return false;
      }
      out = {GraphicsBinding::kXlib, {}, b->xDisplay, b->glxContext, b->glxDrawable};
      break;
    }
    if (s->type == XR_TYPE_GRAPHICS_BINDING_EGL_MNDX && egl_enabled) {
      const auto* b = reinterpret_cast<const XrGraphicsBindingEGLMNDX*>(s);
      if (b->display == EGL_NO_DISPLAY || b->context == EGL_NO_CONTEXT ||
          b->getProcAddress == nullptr) {
        problem = "XrGraphicsBindingEGLMNDX without display, context or getProcAddress";
        return false;
      }
      out = {GraphicsBinding::kEgl, {}, b->display, b->context, 0};
      break;
    }
  }
  if (out.binding != GraphicsBinding::kNone && !load_gl(out.binding, out.gl)) {
    problem = "the GL functions the runtime needs are missing (glTexStorage2D needs GL 4.2)";
    return false;
  }
  return true;  // an OpenGL binding, or none: a headless session if the instance allows one
}

BoundContext::BoundContext(const SessionGraphics& graphics) : graphics_(graphics) {
  switch (graphics.binding) {
    case GraphicsBinding::kXlib: {
      auto* context = static_cast<GLXContext>(graphics.context);
      if (glXGetCurrentContext() == context) {
        ok_ = true;
        return;
      }
      previous_display_ = glXGetCurrentDisplay();
      previous_context_ = glXGetCurrentContext();
      previous_draw_ = glXGetCurrentDrawable();
      previous_read_ = glXGetCurrentReadDrawable();
      ok_ = glXMakeContextCurrent(static_cast<Display*>(graphics.display), graphics.drawable,
                                  graphics.drawable, context) == True;
      switched_ = ok_;
      return;
    }
    case GraphicsBinding::kEgl: {
      auto* context = static_cast<EGLContext>(graphics.context);
      if (eglGetCurrentContext() == context) {
        ok_ = true;
        return;
      }
      previous_display_ = eglGetCurrentDisplay();
      previous_context_ = eglGetCurrentContext();
      previous_draw_ = reinterpret_cast<std::uintptr_t>(eglGetCurrentSurface(EGL_DRAW));
      previous_read_ = reinterpret_cast<std::uintptr_t>(eglGetCurrentSurface(EGL_READ));
      ok_ = eglMakeCurrent(static_cast<EGLDisplay>(graphics.display), EGL_NO_SURFACE,
                           EGL_NO_SURFACE, context) == EGL_TRUE;
      switched_ = ok_;
      return;
    }
    case GraphicsBinding::kNone:
      return;
  }
}

BoundContext::~BoundContext() {
  if (!switched_) {
    return;
  }
  if (graphics_.binding == GraphicsBinding::kXlib) {
    if (previous_context_ != nullptr) {
      glXMakeContextCurrent(static_cast<Display*>(previous_display_), previous_draw_,
                            previous_read_, static_cast<GLXContext>(previous_context_));
    } else {
      glXMakeContextCurrent(static_cast<Display*>(graphics_.display), None, None, nullptr);
    }
  } else if (previous_context_ != EGL_NO_CONTEXT) {
    eglMakeCurrent(previous_display_, reinterpret_cast<EGLSurface>(previous_draw_),
                   reinterpret_cast<EGLSurface>(previous_read_), previous_context_);
  } else {
    eglMakeCurrent(static_cast<EGLDisplay>(graphics_.display), EGL_NO_SURFACE, EGL_NO_SURFACE,
                   EGL_NO_CONTEXT);
  }
}

}  // namespace deixis::xrt
