#pragma once
// The head-locked panel (render/scene.h, HeadPanel): its lines as label geometry
// (render/label_text.h) in one vertex buffer, rebuilt only when the text changes, and drawn as
// plates facing the panel's +z over everything else. Blended so that a see-through headset's
// layer keeps premultiplied alpha (xr/blend_mode.h): colour over, alpha accumulated.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "render/gpu_mesh.h"
#include "render/label_text.h"
#include "render/programs.h"
#include "render/scene.h"

namespace deixis::render {

class PanelPass {
 public:
  static constexpr std::size_t kMaxLines = 12;  // more are not drawn

  PanelPass();
  void draw(const HeadPanel& panel, const Mat4& view_projection, const OverlayProgram& overlay,
            const RendererOptions& options);

 private:
  // Rebuilds the geometry when `panel`'s lines differ from those uploaded; once its buffers have
  // grown to the longest text seen, that allocates nothing either.
  void set_text(const HeadPanel& panel, const RendererOptions& options);

  std::string text_;     // the lines uploaded, each ended by '\n'
  std::string scratch_;  // this frame's lines, joined the same way
  std::array<LabelExtent, kMaxLines> lines_{};
  std::size_t line_count_ = 0;
  float width_ = 0.0f;  // font pixels: the widest line's plate
  std::vector<OverlayVertex> vertices_;
  LabelScratch scratch_labels_;
  GlBuffer buffer_;
  GlVertexArray array_;
};

}  // namespace deixis::render
