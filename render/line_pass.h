#pragma once
// Debug lines (e.g. the eye–fingertip ray), streamed every frame into a buffer that only grows.

#include <span>
#include <vector>

#include "render/gpu_mesh.h"
#include "render/programs.h"

namespace deixis::render {

class LinePass {
 public:
  LinePass();
  void draw(std::span<const DebugLine> lines, const Mat4& view_projection,
            const OverlayProgram& overlay);

 private:
  GlBuffer vertices_;
  GlVertexArray vertex_array_;
  std::size_t capacity_ = 0;  // vertices the buffer holds
  std::vector<OverlayVertex> staging_;
};

}  // namespace deixis::render
