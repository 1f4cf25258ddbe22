#include "xr/swapchains.h"

#include <EGL/egl.h>

#include "render/gl.h"  // before OpenXR's platform header: the EGL and GL types
// XR_USE_GRAPHICS_API_OPENGL is set for this library by CMake.
#include <openxr/openxr_platform.h>

#include <algorithm>
#include <string>

#include "core/error.h"

namespace deixis::xr {

namespace {

// Preferred colour formats, best first. The renderer's colours are display-referred, already
// what a desktop shows as sRGB (no conversion, decision 29), so an sRGB swapchain must store them
// unconverted: the compositor decodes sRGB images, and the headset shows what the desktop does.
// (On an RGBA8 swapchain the compositor takes the same bytes as linear and the picture is darker;
// runtimes offer sRGB swapchains, so that is a fallback only.) Decision 47.
constexpr std::int64_t kColourFormats[] = {GL_SRGB8_ALPHA8, GL_RGBA8};

}  // namespace

Swapchains::Swapchains(const Instance& instance, const GlSession& session)
    : instance_(instance.handle()) {
  if (session.headless()) {
    return;
  }
  const XrInstance xi = instance_;
  std::uint32_t n = 0;
  XR_CHECK(xi, xrEnumerateSwapchainFormats(session.handle(), 0, &n, nullptr));
  std::vector<std::int64_t> formats(n);
  XR_CHECK(xi, xrEnumerateSwapchainFormats(session.handle(), n, &n, formats.data()));
  for (const std::int64_t f : kColourFormats) {
    if (format_ == 0 && std::find(formats.begin(), formats.end(), f) != formats.end()) {
      format_ = f;
    }
  }
  if (format_ == 0) {
    throw Error("the OpenXR runtime offers neither GL_SRGB8_ALPHA8 nor GL_RGBA8 swapchains");
  }
  try {
    for (const XrViewConfigurationView& config : instance.view_config().views) {
      View view;
      view.width = static_cast<std::int32_t>(config.recommendedImageRectWidth);
      view.height = static_cast<std::int32_t>(config.recommendedImageRectHeight);
      XrSwapchainCreateInfo ci{};
      ci.type = XR_TYPE_SWAPCHAIN_CREATE_INFO;
      ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
      ci.format = format_;
      ci.sampleCount = 1;
      ci.width = config.recommendedImageRectWidth;
      ci.height = config.recommendedImageRectHeight;
      ci.faceCount = 1;
      ci.arraySize = 1;
      ci.mipCount = 1;
      XR_CHECK(xi, xrCreateSwapchain(session.handle(), &ci, &view.swapchain));
      views_.push_back(view);
      View& v = views_.back();
      std::uint32_t images = 0;
      XR_CHECK(xi, xrEnumerateSwapchainImages(v.swapchain, 0, &images, nullptr));
      XrSwapchainImageOpenGLKHR blank{};
      blank.type = XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR;
      std::vector<XrSwapchainImageOpenGLKHR> gl(images, blank);
      XR_CHECK(
          xi, xrEnumerateSwapchainImages(v.swapchain, images, &images,
                                         reinterpret_cast<XrSwapchainImageBaseHeader*>(gl.data())));
      glGenRenderbuffers(1, &v.depth);
      glBindRenderbuffer(GL_RENDERBUFFER, v.depth);
      glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, v.width, v.height);
      glBindRenderbuffer(GL_RENDERBUFFER, 0);
      v.framebuffers.assign(images, 0);
      glGenFramebuffers(static_cast<GLsizei>(images), v.framebuffers.data());
      for (std::uint32_t k = 0; k < images; ++k) {
        glBindFramebuffer(GL_FRAMEBUFFER, v.framebuffers[k]);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, gl[k].image, 0);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, v.depth);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE) {
          glBindFramebuffer(GL_FRAMEBUFFER, 0);
          throw Error("an OpenXR swapchain image does not make a complete framebuffer (status " +
                      std::to_string(status) + ")");
        }
      }
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      render::check_gl("xr::Swapchains");
    }
  } catch (...) {
    destroy();
    throw;
  }
}

Swapchains::~Swapchains() {
  destroy();
}

void Swapchains::destroy() {
  for (View& v : views_) {
    if (!v.framebuffers.empty()) {
      glDeleteFramebuffers(static_cast<GLsizei>(v.framebuffers.size()), v.framebuffers.data());
    }
    if (v.depth != 0) {
      glDeleteRenderbuffers(1, &v.depth);
    }
    xrDestroySwapchain(v.swapchain);
  }
  views_.clear();
}

render::RenderTarget Swapchains::acquire(std::uint32_t i) {
  View& v = views_.at(i);
  XrSwapchainImageAcquireInfo ai{XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO, nullptr};
  std::uint32_t image = 0;
  XR_CHECK(instance_, xrAcquireSwapchainImage(v.swapchain, &ai, &image));
  XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO, nullptr, XR_INFINITE_DURATION};
  XR_CHECK(instance_, xrWaitSwapchainImage(v.swapchain, &wi));
  if (image >= v.framebuffers.size()) {
    throw Error("xrAcquireSwapchainImage returned image " + std::to_string(image) + " of " +
                std::to_string(v.framebuffers.size()));
  }
  // Store the renderer's bytes as they are: no sRGB encoding on write (see kColourFormats).
  glDisable(GL_FRAMEBUFFER_SRGB);
  return {v.framebuffers[image], v.width, v.height};
}

void Swapchains::release(std::uint32_t i) {
  XrSwapchainImageReleaseInfo ri{XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO, nullptr};
  XR_CHECK(instance_, xrReleaseSwapchainImage(views_.at(i).swapchain, &ri));
}

XrSwapchainSubImage Swapchains::sub_image(std::uint32_t i) const {
  const View& v = views_.at(i);
  XrSwapchainSubImage s{};
  s.swapchain = v.swapchain;
  s.imageRect.offset = {0, 0};
  s.imageRect.extent = {v.width, v.height};
  s.imageArrayIndex = 0;
  return s;
}

}  // namespace deixis::xr
