#include "eval/figure.h"

#include <algorithm>
#include <cstdio>

#include "dataset/raster.h"

namespace deixis::eval {

namespace {

using dataset::Canvas;
using dataset::Rgb;

constexpr int kPanelWidth = 360;
constexpr int kPanelHeight = 260;
constexpr int kMargin = 48;
constexpr std::array<const char*, 4> kTitles = {"MPJPE [cm]", "MPJRE [deg]", "MPJLVE [cm/s]",
                                                "MPJAVE [deg/s]"};
constexpr std::array<Rgb, 4> kColours = {Rgb{31, 119, 180}, Rgb{214, 39, 40}, Rgb{44, 160, 44},
                                         Rgb{148, 103, 189}};

std::string label(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, v < 10.0 ? "%.2f" : "%.1f", v);
  return buffer;
}

void panel(Canvas& canvas, int x0, int y0, std::size_t metric,
           std::span<const Figure5Series> series) {
  const Rgb axis{60, 60, 60};
  const int left = x0 + kMargin, right = x0 + kPanelWidth - 12;
  const int top = y0 + 28, bottom = y0 + kPanelHeight - 30;
  double top_value = 0.0;
  for (const Figure5Series& s : series) {
    for (const double v : s.values[metric]) {
      top_value = std::max(top_value, v);
    }
  }
  top_value = top_value > 0.0 ? top_value * 1.1 : 1.0;
  canvas.text(static_cast<float>(left), static_cast<float>(y0 + 8), kTitles[metric], axis, 1.5f);
  canvas.line(static_cast<float>(left), static_cast<float>(bottom), static_cast<float>(right),
              static_cast<float>(bottom), axis);
  canvas.line(static_cast<float>(left), static_cast<float>(top), static_cast<float>(left),
              static_cast<float>(bottom), axis);
  canvas.text(static_cast<float>(x0 + 4), static_cast<float>(top), label(top_value), axis);
  canvas.text(static_cast<float>(x0 + 4), static_cast<float>(bottom - 8), "0", axis);
  const auto px = [&](double seconds) {
    return static_cast<float>(left + (seconds - 0.1) / 1.0 * (right - left));
  };
  const auto py = [&](double v) {
    return static_cast<float>(bottom - v / top_value * (bottom - top));
  };
  for (const double s : {0.2, 0.4, 0.6, 0.8, 1.0}) {
    canvas.line(px(s), static_cast<float>(bottom), px(s), static_cast<float>(bottom + 4), axis);
    canvas.text(px(s) - 8.0f, static_cast<float>(bottom + 8), label(s) + "s", axis);
  }
  for (std::size_t k = 0; k < series.size(); ++k) {
    const Figure5Series& s = series[k];
    const Rgb colour = kColours[k % kColours.size()];
    for (std::size_t i = 0; i < s.seconds.size(); ++i) {
      const float x = px(s.seconds[i]), y = py(s.values[metric][i]);
      canvas.disc(x, y, 3.0f, colour);
      if (i > 0) {
        canvas.line(px(s.seconds[i - 1]), py(s.values[metric][i - 1]), x, y, colour, 2.0f);
      }
    }
  }
}

}  // namespace

void write_figure5(std::span<const Figure5Series> series, const std::filesystem::path& path) {
  const int legend = 24 + 14 * static_cast<int>(series.size());
  Canvas canvas(2 * kPanelWidth, 2 * kPanelHeight + legend, Rgb{255, 255, 255});
  for (std::size_t m = 0; m < 4; ++m) {
    panel(canvas, static_cast<int>(m % 2) * kPanelWidth, static_cast<int>(m / 2) * kPanelHeight, m,
          series);
  }
  canvas.text(12.0f, static_cast<float>(2 * kPanelHeight + 4),
              "Missed tracking duration vs. motion error against the clean run (mean over "
              "test subjects)",
              Rgb{0, 0, 0});
  for (std::size_t k = 0; k < series.size(); ++k) {
    const float y = static_cast<float>(2 * kPanelHeight + 20 + 14 * static_cast<int>(k));
    canvas.rect(12, static_cast<int>(y), 24, static_cast<int>(y) + 8,
                kColours[k % kColours.size()]);
    canvas.text(30.0f, y, series[k].label, Rgb{0, 0, 0});
  }
  canvas.write_png(path);
}

}  // namespace deixis::eval
