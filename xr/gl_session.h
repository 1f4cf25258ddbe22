#pragma once
// The OpenXR session: with XR_KHR_opengl_enable's EGL binding (XR_MNDX_egl_enable) on the EGL
// context current on this thread (the renderer's HeadlessContext), with its Xlib binding on the
// current GLX context (a GLFW window's) where the runtime has no EGL binding (xr/gl_context.h
// makes the right context), or without graphics under XR_MND_headless. It owns the session's
// reference spaces: STAGE (the room; the floor origin) as the world every pose is given in, and
// VIEW (the head).

#include <openxr/openxr.h>

#include "xr/instance.h"

namespace deixis::xr {

class GlSession {
 public:
  // An OpenGL session needs the context its binding takes current (EGL, or GLX without
  // XR_MNDX_egl_enable; xr/gl_context.h) of at least the OpenGL version the runtime requires;
  // throws deixis::Error otherwise or when a call fails.
  explicit GlSession(const Instance& instance);
  ~GlSession();
  GlSession(const GlSession&) = delete;
  GlSession& operator=(const GlSession&) = delete;

  XrSession handle() const { return session_; }
  bool headless() const { return headless_; }
  XrSpace stage() const { return stage_; }  // the world (STAGE, or LOCAL where no STAGE)
  XrSpace view() const { return view_; }    // the head

 private:
  bool headless_ = false;
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace stage_ = XR_NULL_HANDLE;
  XrSpace view_ = XR_NULL_HANDLE;
};

}  // namespace deixis::xr
