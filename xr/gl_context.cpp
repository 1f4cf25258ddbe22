#include "xr/gl_context.h"

#include "render/headless_context.h"
#include "render/window_context.h"

namespace deixis::xr {

std::unique_ptr<render::Context> make_gl_context(const Instance& instance) {
  const Features& f = instance.features();
  if (f.headless || f.egl) {
    return std::make_unique<render::HeadlessContext>(16, 16);  // the views go to the swapchains
  }
  // Hidden and tiny: nothing is drawn into the window; it only carries the GLX context.
  return std::make_unique<render::WindowContext>(render::WindowOptions{
      .width = 16, .height = 16, .title = "deixis xr", .visible = false, .vsync = false});
}

}  // namespace deixis::xr
