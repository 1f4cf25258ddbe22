#pragma once
// Object names as geometry: stb_easy_font's built-in bitmap font (Debian's libstb, no font files)
// turned into triangles in *label space*: x to the right and y up, in font pixels, centred on
// x = 0 with the bottom of a dark backing plate at y = 0. The renderer places each label as a
// billboard above its object (render/renderer.cpp).

#include <string>
#include <string_view>
#include <vector>

#include "render/gpu_mesh.h"
#include "render/skinned_mesh.h"

namespace deixis::render {

struct LabelExtent {
  GLint first = 0;      // first vertex in the vertex array it was appended to
  GLsizei count = 0;    // vertices (triangles × 3)
  float width = 0.0f;   // font pixels, backing plate included
  float height = 0.0f;  // font pixels, backing plate included
};

// Appends `text` (printable ASCII; anything else is drawn as '?') over its backing plate to
// `vertices`: the plate's triangles first, then the glyphs', so drawing them in order with depth
// writes off needs no depth offset.
LabelExtent append_label(std::string_view text, const Colour& text_colour,
                         const Colour& backing_colour, std::vector<OverlayVertex>& vertices);

struct FontVertex {  // stb_easy_font's vertex record (stb_easy_font.h): x, y, z, RGBA bytes
  float x, y, z;
  unsigned char rgba[4];
};
// Buffers append_label works in. A caller that rebuilds labels often keeps one, so that once
// they have grown to its longest text no rebuild allocates (vertices kept with their capacity).
struct LabelScratch {
  std::string line;               // the text, printable
  std::vector<FontVertex> quads;  // stb_easy_font's output
};
LabelExtent append_label(std::string_view text, const Colour& text_colour,
                         const Colour& backing_colour, std::vector<OverlayVertex>& vertices,
                         LabelScratch& scratch);

}  // namespace deixis::render
