#include "dataset/raster.h"

#include <stb_easy_font.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace deixis::dataset {

namespace {

std::uint8_t mix(std::uint8_t a, std::uint8_t b, float alpha) {
  return static_cast<std::uint8_t>(
      std::lround(static_cast<float>(a) + alpha * (static_cast<float>(b) - static_cast<float>(a))));
}

// Distance from p to the segment a–b.
float segment_distance(float px, float py, float ax, float ay, float bx, float by) {
  const float dx = bx - ax;
  const float dy = by - ay;
  const float len2 = dx * dx + dy * dy;
  float t = len2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / len2 : 0.0f;
  t = std::clamp(t, 0.0f, 1.0f);
  const float ex = ax + t * dx - px;
  const float ey = ay + t * dy - py;
  return std::sqrt(ex * ex + ey * ey);
}

}  // namespace

Canvas::Canvas(int width, int height, Rgb background)
    : width_(width),
      height_(height),
      clip_x1_(width),
      clip_y1_(height),
      pixels_(static_cast<std::size_t>(width * height) * 3) {
  for (std::size_t i = 0; i < pixels_.size(); i += 3) {
    pixels_[i] = background.r;
    pixels_[i + 1] = background.g;
    pixels_[i + 2] = background.b;
  }
}

Rgb Canvas::at(int x, int y) const {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                         static_cast<std::size_t>(x)) *
                        3;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2]};
}

void Canvas::clip(int x0, int y0, int x1, int y1) {
  clip_x0_ = std::max(0, x0);
  clip_y0_ = std::max(0, y0);
  clip_x1_ = std::min(width_, x1);
  clip_y1_ = std::min(height_, y1);
}

void Canvas::blend(int x, int y, Rgb c, float alpha) {
  if (x < clip_x0_ || y < clip_y0_ || x >= clip_x1_ || y >= clip_y1_ || alpha <= 0.0f) {
    return;
  }
  alpha = std::min(alpha, 1.0f);
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                         static_cast<std::size_t>(x)) *
                        3;
  pixels_[i] = mix(pixels_[i], c.r, alpha);
  pixels_[i + 1] = mix(pixels_[i + 1], c.g, alpha);
  pixels_[i + 2] = mix(pixels_[i + 2], c.b, alpha);
}

void Canvas::line(float x0, float y0, float x1, float y1, Rgb c, float width, float alpha) {
  if (!std::isfinite(x0) || !std::isfinite(y0) || !std::isfinite(x1) || !std::isfinite(y1)) {
    return;
  }
  const float half = 0.5f * width;
  const int xa = std::max(0, static_cast<int>(std::floor(std::min(x0, x1) - half - 1)));
  const int xb = std::min(width_ - 1, static_cast<int>(std::ceil(std::max(x0, x1) + half + 1)));
  const int ya = std::max(0, static_cast<int>(std::floor(std::min(y0, y1) - half - 1)));
  const int yb = std::min(height_ - 1, static_cast<int>(std::ceil(std::max(y0, y1) + half + 1)));
  for (int y = ya; y <= yb; ++y) {
    for (int x = xa; x <= xb; ++x) {
      const float d = segment_distance(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f,
                                       x0, y0, x1, y1);
      blend(x, y, c, alpha * std::clamp(half + 0.5f - d, 0.0f, 1.0f));
    }
  }
}

void Canvas::circle(float cx, float cy, float radius, Rgb c, float width) {
  const float half = 0.5f * width;
  const int xa = static_cast<int>(std::floor(cx - radius - half - 1));
  const int xb = static_cast<int>(std::ceil(cx + radius + half + 1));
  const int ya = static_cast<int>(std::floor(cy - radius - half - 1));
  const int yb = static_cast<int>(std::ceil(cy + radius + half + 1));
  for (int y = std::max(0, ya); y <= std::min(height_ - 1, yb); ++y) {
    for (int x = std::max(0, xa); x <= std::min(width_ - 1, xb); ++x) {
      const float d =
          std::hypot(static_cast<float>(x) + 0.5f - cx, static_cast<float>(y) + 0.5f - cy);
      blend(x, y, c, std::clamp(half + 0.5f - std::abs(d - radius), 0.0f, 1.0f));
    }
  }
}

void Canvas::disc(float cx, float cy, float radius, Rgb c, float alpha) {
  const int xa = static_cast<int>(std::floor(cx - radius - 1));
  const int xb = static_cast<int>(std::ceil(cx + radius + 1));
  const int ya = static_cast<int>(std::floor(cy - radius - 1));
  const int yb = static_cast<int>(std::ceil(cy + radius + 1));
  for (int y = std::max(0, ya); y <= std::min(height_ - 1, yb); ++y) {
    for (int x = std::max(0, xa); x <= std::min(width_ - 1, xb); ++x) {
      const float d =
          std::hypot(static_cast<float>(x) + 0.5f - cx, static_cast<float>(y) + 0.5f - cy);
      blend(x, y, c, alpha * std::clamp(radius + 0.5f - d, 0.0f, 1.0f));
    }
  }
}

void Canvas::rect(int x0, int y0, int x1, int y1, Rgb c, float alpha) {
  for (int y = std::max(0, y0); y < std::min(height_, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(width_, x1); ++x) {
      blend(x, y, c, alpha);
    }
  }
}

void Canvas::text(float x, float y, std::string_view s, Rgb c, float scale) {
  // stb_easy_font emits axis-aligned quads (4 vertices of x, y, z, rgba: 16 bytes each).
  std::string str(s);
  static thread_local std::vector<char> buffer(1 << 16);
  const int quads = stb_easy_font_print(0, 0, str.data(), nullptr, buffer.data(),
                                        static_cast<int>(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    float v[4][4];
    std::copy_n(buffer.data() + q * 64, 64, reinterpret_cast<char*>(v));
    const float qx0 = std::min(v[0][0], v[2][0]);
    const float qy0 = std::min(v[0][1], v[2][1]);
    const float qx1 = std::max(v[0][0], v[2][0]);
    const float qy1 = std::max(v[0][1], v[2][1]);
    rect(static_cast<int>(std::lround(x + qx0 * scale)),
         static_cast<int>(std::lround(y + qy0 * scale)),
         static_cast<int>(std::lround(x + qx1 * scale)),
         static_cast<int>(std::lround(y + qy1 * scale)), c);
  }
}

void Canvas::write_png(const std::filesystem::path& path) const {
  const std::string name = path.string();
  if (stbi_write_png(name.c_str(), width_, height_, 3, pixels_.data(), width_ * 3) == 0) {
    throw Error(name + ": cannot write the PNG");
  }
}

}  // namespace deixis::dataset
