#pragma once
// A tiny software rasteriser for plots (the capture's previews, the evaluation's Fig. 5):
// anti-aliased lines and circles, filled rectangles, stb_easy_font text, PNG output through
// stb_image_write (Debian's libstb-dev).

#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

namespace deixis::dataset {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

class Canvas {
 public:
  Canvas(int width, int height, Rgb background);

  int width() const { return width_; }
  int height() const { return height_; }
  Rgb at(int x, int y) const;

  // Drawing outside [x0, x1) × [y0, y1) is ignored until the clip is reset.
  void clip(int x0, int y0, int x1, int y1);
  void reset_clip() { clip(0, 0, width_, height_); }

  // Mixes `colour` into a pixel with coverage `alpha` ∈ [0, 1]; outside the canvas: ignored.
  void blend(int x, int y, Rgb colour, float alpha);
  void line(float x0, float y0, float x1, float y1, Rgb colour, float width = 1.0f,
            float alpha = 1.0f);
  void circle(float cx, float cy, float radius, Rgb colour, float width = 1.0f);
  void disc(float cx, float cy, float radius, Rgb colour, float alpha = 1.0f);
  void rect(int x0, int y0, int x1, int y1, Rgb colour, float alpha = 1.0f);
  // Text with its top-left corner at (x, y); `scale` multiplies the 8-pixel-high font.
  void text(float x, float y, std::string_view s, Rgb colour, float scale = 1.0f);

  // Throws deixis::Error naming the path if it cannot be written.
  void write_png(const std::filesystem::path& path) const;

 private:
  int width_;
  int height_;
  int clip_x0_ = 0, clip_y0_ = 0, clip_x1_, clip_y1_;
  std::vector<std::uint8_t> pixels_;  // RGB, row-major
};

}  // namespace deixis::dataset
