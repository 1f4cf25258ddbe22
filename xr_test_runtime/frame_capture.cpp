#include "xr_test_runtime/frame_capture.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <fstream>
#include <vector>

namespace deixis::xrt {

RecordedImage capture_view(const GlFunctions& gl, const SwapchainObject& swapchain,
                           std::uint32_t image, const XrRect2Di& rect, const std::string& file) {
  RecordedImage out;
  if (image >= swapchain.textures.size() ||
      (swapchain.format != GL_RGBA8 && swapchain.format != GL_SRGB8_ALPHA8)) {
    return out;
  }
  const std::size_t w = swapchain.width, h = swapchain.height;
  std::vector<unsigned char> pixels(w * h * 4);
  while (gl.GetError() != GL_NO_ERROR) {
    // errors the application left: not ours to report
  }
  gl.BindTexture(GL_TEXTURE_2D, swapchain.textures[image]);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.GetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  gl.BindTexture(GL_TEXTURE_2D, 0);
  if (gl.GetError() != GL_NO_ERROR) {
    return out;
  }
  out.width = static_cast<std::uint32_t>(rect.extent.width);
  out.height = static_cast<std::uint32_t>(rect.extent.height);
  std::ofstream pam(file, std::ios::binary);
  pam << "P7\nWIDTH " << out.width << "\nHEIGHT " << out.height
      << "\nDEPTH 4\nMAXVAL 255\nTUPLTYPE RGB_ALPHA\nENDHDR\n";
  // GL rows go up from the bottom; the file's go down from the top.
  for (std::uint32_t row = 0; row < out.height; ++row) {
    const std::size_t y = static_cast<std::size_t>(rect.offset.y) + out.height - 1 - row;
    const unsigned char* line = &pixels[(y * w + static_cast<std::size_t>(rect.offset.x)) * 4];
    pam.write(reinterpret_cast<const char*>(line), static_cast<std::streamsize>(out.width) * 4);
    for (std::uint32_t x = 0; x < out.width; ++x) {
      const unsigned char a = line[x * 4 + 3];
      ++(a == 0 ? out.transparent : a == 255 ? out.opaque : out.partial);
    }
  }
  if (pam) {
    out.file = file;
  }
  return out;
}

}  // namespace deixis::xrt
