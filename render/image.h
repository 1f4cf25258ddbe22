#pragma once
// Frames on the CPU: 8-bit RGB, row 0 at the top (as PNG files and ffmpeg's rawvideo store them;
// OpenGL's rows start at the bottom, so read_pixels flips). Screenshots are PNGs written and read
// with Debian's stb_image_write and stb_image.

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "render/render_target.h"

namespace deixis::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width × height × 3, row-major from the top row

  std::array<std::uint8_t, 3> pixel(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

// The target's colour buffer (a window's back buffer for framebuffer 0), top row first. Waits for
// the frame to finish. The second form reuses `out`'s storage: no allocation once it is sized.
Image read_pixels(const RenderTarget& target);
void read_pixels(const RenderTarget& target, Image& out);

// Writes `image` as a PNG. Throws deixis::Error naming the path when the image is empty or
// inconsistent, the directory does not exist, or the file cannot be written.
void write_png(const Image& image, const std::filesystem::path& path);

// Reads a PNG (any channel layout, converted to RGB). Throws deixis::Error naming the path and
// the decoder's reason.
Image read_png(const std::filesystem::path& path);

}  // namespace deixis::render
