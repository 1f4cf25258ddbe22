#pragma once
// One colour swapchain per view (and a depth renderbuffer per view), each image wrapped in a GL
// framebuffer so the renderer draws into it like any other render::RenderTarget. Headless
// sessions have none. Needs the session's GL context current for its whole life.

#include <openxr/openxr.h>

#include <cstdint>
#include <vector>

#include "render/render_target.h"
#include "xr/gl_session.h"
#include "xr/instance.h"

namespace deixis::xr {

class Swapchains {
 public:
  // Creates a swapchain of each view's recommended size (an sRGB or RGBA8 colour format the
  // runtime offers) and framebuffers for every image. Throws deixis::Error.
  Swapchains(const Instance& instance, const GlSession& session);
  ~Swapchains();
  Swapchains(const Swapchains&) = delete;
  Swapchains& operator=(const Swapchains&) = delete;

  std::uint32_t count() const { return static_cast<std::uint32_t>(views_.size()); }
  // Acquires and waits for view `i`'s next image; draw into the returned target, then release.
  render::RenderTarget acquire(std::uint32_t i);
  void release(std::uint32_t i);
  // For XrCompositionLayerProjectionView::subImage.
  XrSwapchainSubImage sub_image(std::uint32_t i) const;
  std::int64_t format() const { return format_; }

 private:
  struct View {
    XrSwapchain swapchain = XR_NULL_HANDLE;
    std::int32_t width = 0;
    std::int32_t height = 0;
    std::vector<std::uint32_t> framebuffers;  // one per image
    std::uint32_t depth = 0;                  // renderbuffer shared by the images
  };
  void destroy();

  XrInstance instance_;
  std::int64_t format_ = 0;
  std::vector<View> views_;
};

}  // namespace deixis::xr
