#include "render/label_text.h"

#include <algorithm>
#include <limits>
#include <string>

#include <stb_easy_font.h>

namespace deixis::render {
namespace {

static_assert(sizeof(FontVertex) == 16);

constexpr float kPadding = 2.0f;  // font pixels of backing plate around the glyphs

// stb_easy_font indexes its glyph table with (char − 32) unchecked, so only printable ASCII may
// reach it; a newline would start a second line, which a label does not have.
void printable(std::string_view text, std::string& out) {
  out.assign(text);
  for (char& c : out) {
    if (c < 32 || c > 126) {
      c = '?';
    }
  }
}

OverlayVertex vertex(float x, float y, const Colour& colour) {
  return {{x, y, 0.0f}, {colour.x(), colour.y(), colour.z(), colour.w()}};
}

void append_rectangle(std::vector<OverlayVertex>& out, float x0, float y0, float x1, float y1,
                      const Colour& colour) {
  out.insert(out.end(), {vertex(x0, y0, colour), vertex(x1, y0, colour), vertex(x1, y1, colour),
                         vertex(x0, y0, colour), vertex(x1, y1, colour), vertex(x0, y1, colour)});
}

}  // namespace

LabelExtent append_label(std::string_view text, const Colour& text_colour,
                         const Colour& backing_colour, std::vector<OverlayVertex>& vertices) {
  LabelScratch scratch;
  return append_label(text, text_colour, backing_colour, vertices, scratch);
}

LabelExtent append_label(std::string_view text, const Colour& text_colour,
                         const Colour& backing_colour, std::vector<OverlayVertex>& vertices,
                         LabelScratch& scratch) {
  std::string& line = scratch.line;
  printable(text, line);
  // ~270 bytes per character on average (stb_easy_font.h); give it room for the worst glyphs.
  std::vector<FontVertex>& quads = scratch.quads;
  quads.resize(line.size() * 64 + 64);
  const int quad_count = stb_easy_font_print(0.0f, 0.0f, line.data(), nullptr, quads.data(),
                                             static_cast<int>(quads.size() * sizeof(FontVertex)));
  quads.resize(static_cast<std::size_t>(quad_count) * 4);

  // stb's y grows downwards; label space's grows upwards.
  float min_x = std::numeric_limits<float>::max();
  float max_x = std::numeric_limits<float>::lowest();
  float min_y = std::numeric_limits<float>::max();
  float max_y = std::numeric_limits<float>::lowest();
  for (FontVertex& v : quads) {
    v.y = -v.y;
    min_x = std::min(min_x, v.x);
    max_x = std::max(max_x, v.x);
    min_y = std::min(min_y, v.y);
    max_y = std::max(max_y, v.y);
  }
  if (quads.empty()) {  // blank text: a small empty plate
    min_x = max_x = min_y = max_y = 0.0f;
  }
  const float shift_x = -0.5f * (min_x + max_x);
  const float shift_y = kPadding - min_y;
  const float width = max_x - min_x + 2.0f * kPadding;
  const float height = max_y - min_y + 2.0f * kPadding;

  LabelExtent extent;
  extent.first = static_cast<GLint>(vertices.size());
  append_rectangle(vertices, -0.5f * width, 0.0f, 0.5f * width, height, backing_colour);
  for (std::size_t q = 0; q < quads.size(); q += 4) {
    const FontVertex& a = quads[q];
    const FontVertex& c = quads[q + 2];
    append_rectangle(vertices, a.x + shift_x, a.y + shift_y, c.x + shift_x, c.y + shift_y,
                     text_colour);
  }
  extent.count = static_cast<GLsizei>(vertices.size()) - extent.first;
  extent.width = width;
  extent.height = height;
  return extent;
}

}  // namespace deixis::render
