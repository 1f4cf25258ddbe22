#pragma once
// Where a frame is drawn: a framebuffer (0 is a window's back buffer) and its size in pixels. An
// OpenXR front end wraps each eye's swapchain image in a framebuffer and passes it the same way.

#include "render/gl.h"

namespace deixis::render {

struct RenderTarget {
  GLuint framebuffer = 0;
  int width = 0;
  int height = 0;
};

}  // namespace deixis::render
