#include "render/panel_pass.h"

#include <algorithm>

namespace deixis::render {

namespace {
constexpr std::size_t kTextReserved = 2048;  // bytes of panel text compared without allocating
}  // namespace

PanelPass::PanelPass() : buffer_(create_buffer()), array_(overlay_vertex_array(buffer_.get())) {
  text_.reserve(kTextReserved);
  scratch_.reserve(kTextReserved);
}

void PanelPass::set_text(const HeadPanel& panel, const RendererOptions& options) {
  scratch_.clear();
  const std::size_t count = std::min(panel.lines.size(), kMaxLines);
  for (std::size_t i = 0; i < count; ++i) {
    scratch_.append(panel.lines[i]);
    scratch_.push_back('\n');
  }
  if (scratch_ == text_) {  // one '\n' per line: the same text is the same number of lines
    return;
  }
  text_.swap(scratch_);
  vertices_.clear();
  width_ = 0.0f;
  for (std::size_t i = 0; i < count; ++i) {
    lines_[i] = append_label(panel.lines[i], options.label_text, options.label_backing, vertices_,
                             scratch_labels_);
    width_ = std::max(width_, lines_[i].width);
  }
  line_count_ = count;
  glNamedBufferData(buffer_.get(),
                    static_cast<GLsizeiptr>(vertices_.size() * sizeof(OverlayVertex)),
                    vertices_.empty() ? nullptr : vertices_.data(), GL_DYNAMIC_DRAW);
}

void PanelPass::draw(const HeadPanel& panel, const Mat4& view_projection,
                     const OverlayProgram& overlay, const RendererOptions& options) {
  set_text(panel, options);
  if (line_count_ == 0) {
    return;
  }
  const GLuint p = overlay.program.id();
  glProgramUniformMatrix4fv(p, overlay.view_projection, 1, GL_FALSE, view_projection.data());
  glUseProgram(p);
  glBindVertexArray(array_.get());
  // Label space is in font pixels, each line centred on x = 0 with its plate's bottom at y = 0:
  // scale to metres, stack the lines downwards from the panel's top, and left-align them.
  const float line_pixels = std::max(lines_[0].height, 1.0f);
  const float scale = panel.line_height / line_pixels;
  const float half_width = 0.5f * width_;
  const float half_height = 0.5f * line_pixels * static_cast<float>(line_count_);
  const Mat3& R = panel.T_world_panel.rotation;
  for (std::size_t i = 0; i < line_count_; ++i) {
    const LabelExtent& line = lines_[i];
    const Vec3 offset(0.5f * line.width - half_width,
                      half_height - line_pixels * static_cast<float>(i + 1), 0.0f);
    Mat4 model = Mat4::Identity();
    model.topLeftCorner<3, 3>() = R * scale;
    model.topRightCorner<3, 1>() = panel.T_world_panel.translation + R * (offset * scale);
    glProgramUniformMatrix4fv(p, overlay.model, 1, GL_FALSE, model.data());
    glDrawArrays(GL_TRIANGLES, line.first, line.count);
  }
}

}  // namespace deixis::render
