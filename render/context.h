#pragma once
// The one small interface the front ends share: a current OpenGL 4.5 core context and the target
// each frame is drawn into. Two implementations: HeadlessContext (EGL surfaceless, Mesa llvmpipe,
// an offscreen framebuffer) and WindowContext (a GLFW window). The OpenXR front end needs no
// Context of its own: it renders into its swapchain framebuffers with the same Renderer.
//
//   HeadlessContext context(1280, 720);     // or WindowContext
//   Renderer renderer;                       // needs the context current
//   renderer.render(view, context.target());
//   context.present();                       // swap, or finish the frame
//   Image frame = read_pixels(context.target());

#include <string>

#include "render/render_target.h"

namespace deixis::render {

class Context {
 public:
  virtual ~Context() = default;
  Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Where this frame goes (a window's size follows the window).
  virtual RenderTarget target() = 0;
  // Ends the frame: a window swaps buffers; headless waits until the frame is complete.
  virtual void present() = 0;
  // Makes this context current on the calling thread (each is current after construction).
  virtual void make_current() = 0;
  // "EGL surfaceless: llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  virtual std::string description() const = 0;
};

}  // namespace deixis::render
