#pragma once
// The one place that includes OpenGL. GLVND's libOpenGL exports every core entry point, so with
// GL_GLEXT_PROTOTYPES the 4.5 core functions (direct state access included) are plain calls that
// dispatch to the current context, EGL or GLX alike; no loader, no function-pointer tables
// (docs/decisions.md, 26).

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

#include <string>
#include <string_view>

namespace deixis::render {

// The name of a glGetError code ("GL_INVALID_OPERATION"), for messages.
std::string_view gl_error_name(GLenum error);

// Throws deixis::Error naming `where` and every pending GL error; does nothing when none is
// pending. For set-up paths and tests; the per-frame path does not poll errors.
void check_gl(std::string_view where);

// GL_RENDERER and GL_VERSION of the current context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits),
// 4.5 (Core Profile) Mesa 22.3.6", for reports and benchmark headers.
std::string gl_description();

// Throws deixis::Error unless the current context is desktop OpenGL `major`.`minor` or newer.
void require_gl_version(int major, int minor, std::string_view who);

}  // namespace deixis::render
