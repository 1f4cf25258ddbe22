#pragma once
// A framebuffer of our own: an RGBA8 colour texture (so an ImGui panel or a later pass can sample
// it) and a 24-bit depth buffer, the size it was made. Headless rendering draws here; a window
// can too, e.g. for screenshots at another size.

#include "render/gl_object.h"
#include "render/render_target.h"

namespace deixis::render {

class OffscreenTarget {
 public:
  // Throws deixis::Error when the size is not positive or the framebuffer is incomplete.
  OffscreenTarget(int width, int height);

  RenderTarget target() const { return {framebuffer_.get(), width_, height_}; }
  GLuint colour_texture() const { return colour_.get(); }

 private:
  int width_;
  int height_;
  GlTexture colour_;
  GlRenderbuffer depth_;
  GlFramebuffer framebuffer_;
};

}  // namespace deixis::render
