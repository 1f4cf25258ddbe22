#include "render/headless_context.h"

#define EGL_NO_X11 1
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "core/error.h"

namespace deixis::render {
namespace {

std::string egl_error_text(EGLint error) {
  switch (error) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default: {
      char code[16];
      std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(error));
      return std::string("EGL error ") + code;
    }
  }
}

[[noreturn]] void fail(const std::string& step) {
  throw Error("headless context: " + step + " failed: " + egl_error_text(eglGetError()));
}

bool has_extension(const char* extensions, const char* name) {
  if (extensions == nullptr) {
    return false;
  }
  const std::size_t length = std::strlen(name);
  for (const char* p = std::strstr(extensions, name); p != nullptr; p = std::strstr(p + 1, name)) {
    const bool starts = p == extensions || p[-1] == ' ';
    const bool ends = p[length] == ' ' || p[length] == '\0';
    if (starts && ends) {
      return true;
    }
  }
  return false;
}

EGLDisplay surfaceless_display() {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_extension(client, "EGL_MESA_platform_surfaceless")) {
    throw Error(
        "headless context: EGL has no surfaceless platform (EGL_MESA_platform_surfaceless); "
        "install Mesa's EGL driver (Debian: libegl-mesa0, libgl1-mesa-dri; tools/install-deps)");
  }
  EGLDisplay display =
      eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) {
    fail("eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA)");
  }
  EGLint major = 0;
  EGLint minor = 0;
  if (eglInitialize(display, &major, &minor) != EGL_TRUE) {
    fail("eglInitialize on the surfaceless platform");
  }
  return display;
}

EGLContext core_context(EGLDisplay display) {
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  for (const char* needed : {"EGL_KHR_surfaceless_context", "EGL_KHR_no_config_context"}) {
    if (!has_extension(extensions, needed)) {
      throw Error(std::string("headless context: the EGL driver lacks ") + needed);
    }
  }
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    fail("eglBindAPI(EGL_OPENGL_API)");
  }
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    fail("eglCreateContext (desktop OpenGL 4.5 core)");
  }
  if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context) != EGL_TRUE) {
    const std::string error = egl_error_text(eglGetError());
    eglDestroyContext(display, context);
    throw Error("headless context: eglMakeCurrent failed: " + error);
  }
  return context;
}

}  // namespace

HeadlessContext::HeadlessContext(int width, int height) {
  EGLDisplay display = surfaceless_display();
  try {
    context_ = core_context(display);
    display_ = display;
    require_gl_version(4, 5, "headless context");
    offscreen_.emplace(width, height);
  } catch (...) {
    offscreen_.reset();
    if (context_ != nullptr) {
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglDestroyContext(display, context_);
    }
    eglReleaseThread();
    throw;
  }
}

HeadlessContext::~HeadlessContext() {
  // The framebuffer's objects belong to this context; another may be current by now.
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
  offscreen_.reset();
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  // No eglTerminate: the display is the process's one surfaceless display, shared by every
  // HeadlessContext, and terminating it would end the others' contexts too (header comment).
  eglReleaseThread();
}

void HeadlessContext::present() {
  glFinish();
}

void HeadlessContext::make_current() {
  if (eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) != EGL_TRUE) {
    fail("eglMakeCurrent");
  }
}

std::string HeadlessContext::description() const {
  return "EGL surfaceless: " + gl_description();
}

}  // namespace deixis::render
