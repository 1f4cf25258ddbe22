#pragma once
// Rendering without a display (CI, the demo, batch evaluation): an EGL context on Mesa's
// surfaceless platform (EGL_PLATFORM_SURFACELESS_MESA; llvmpipe when there is no GPU), desktop
// OpenGL 4.5 core, drawing into an offscreen framebuffer of a fixed size.
//
// EGL keeps one display per platform per process, and eglTerminate would end every context on it
// at once (Mesa also unloads its driver then). So the display is initialised by the first
// HeadlessContext and stays so until the process exits; each HeadlessContext creates and destroys
// only its own EGL context, and several may exist side by side (each current on one thread at a
// time; make_current() switches).

#include <optional>
#include <string>

#include "render/context.h"
#include "render/offscreen_target.h"

namespace deixis::render {

class HeadlessContext final : public Context {
 public:
  // Throws deixis::Error naming the failing EGL step and its error (no surfaceless platform, no
  // OpenGL 4.5 core context, ...).
  HeadlessContext(int width, int height);
  ~HeadlessContext() override;

  RenderTarget target() override { return offscreen_->target(); }
  void present() override;
  void make_current() override;
  std::string description() const override;

  const OffscreenTarget& offscreen() const { return *offscreen_; }

 private:
  // EGLDisplay and EGLContext are opaque pointers; keeping EGL's headers (and the X11 headers
  // they can pull in) out of this one keeps their macros out of every includer.
  void* display_ = nullptr;
  void* context_ = nullptr;
  std::optional<OffscreenTarget> offscreen_;
};

}  // namespace deixis::render
