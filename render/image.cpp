#include "render/image.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include <stb_image.h>
#include <stb_image_write.h>

#include "core/error.h"
#include "render/gl.h"

namespace deixis::render {

Image read_pixels(const RenderTarget& target) {
  Image image;
  read_pixels(target, image);
  return image;
}

void read_pixels(const RenderTarget& target, Image& out) {
  out.width = target.width;
  out.height = target.height;
  const std::size_t row = static_cast<std::size_t>(target.width) * 3;
  out.rgb.resize(row * static_cast<std::size_t>(target.height));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, target.framebuffer);
  glReadBuffer(target.framebuffer == 0 ? GL_BACK : GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);  // rows of width × 3 bytes, no padding
  glReadPixels(0, 0, target.width, target.height, GL_RGB, GL_UNSIGNED_BYTE, out.rgb.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  // OpenGL returns the bottom row first.
  for (int y = 0; y < target.height / 2; ++y) {
    auto top = out.rgb.begin() + static_cast<std::ptrdiff_t>(y * row);
    auto bottom = out.rgb.begin() + static_cast<std::ptrdiff_t>((target.height - 1 - y) * row);
    std::swap_ranges(top, top + static_cast<std::ptrdiff_t>(row), bottom);
  }
}

void write_png(const Image& image, const std::filesystem::path& path) {
  const std::string name = path.string();
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
    throw Error("cannot write PNG '" + name + "': the image is " + std::to_string(image.width) +
                " x " + std::to_string(image.height) + " with " + std::to_string(image.rgb.size()) +
                " bytes");
  }
  const std::filesystem::path directory = path.parent_path();
  if (!directory.empty() && !std::filesystem::is_directory(directory)) {
    throw Error("cannot write PNG '" + name + "': directory '" + directory.string() +
                "' does not exist");
  }
  errno = 0;
  if (stbi_write_png(name.c_str(), image.width, image.height, 3, image.rgb.data(),
                     image.width * 3) == 0) {
    const int error = errno;
    throw Error("cannot write PNG '" + name +
                "': " + (error != 0 ? std::strerror(error) : "stb_image_write failed"));
  }
}

Image read_png(const std::filesystem::path& path) {
  int width = 0;
  int height = 0;
  int channels = 0;
  stbi_uc* pixels = stbi_load(path.c_str(), &width, &height, &channels, 3);
  if (pixels == nullptr) {
    throw Error("cannot read PNG '" + path.string() + "': " + stbi_failure_reason());
  }
  Image image{width, height, {}};
  image.rgb.assign(pixels, pixels + static_cast<std::size_t>(width) * height * 3);
  stbi_image_free(pixels);
  return image;
}

}  // namespace deixis::render
