#include "render/line_pass.h"

namespace deixis::render {
namespace {

OverlayVertex vertex(const Vec3& p, const Colour& c) {
  return {{p.x(), p.y(), p.z()}, {c.x(), c.y(), c.z(), c.w()}};
}

}  // namespace

LinePass::LinePass()
    : vertices_(create_buffer()), vertex_array_(overlay_vertex_array(vertices_.get())) {}

void LinePass::draw(std::span<const DebugLine> lines, const Mat4& view_projection,
                    const OverlayProgram& overlay) {
  if (lines.empty()) {
    return;
  }
  staging_.clear();
  for (const DebugLine& line : lines) {
    staging_.push_back(vertex(line.from, line.colour));
    staging_.push_back(vertex(line.to, line.colour));
  }
  const auto bytes = static_cast<GLsizeiptr>(staging_.size() * sizeof(OverlayVertex));
  if (staging_.size() > capacity_) {
    capacity_ = staging_.size();
    glNamedBufferData(vertices_.get(), bytes, staging_.data(), GL_STREAM_DRAW);
  } else {
    glNamedBufferSubData(vertices_.get(), 0, bytes, staging_.data());
  }
  const GLuint p = overlay.program.id();
  const Mat4 identity = Mat4::Identity();
  glProgramUniformMatrix4fv(p, overlay.view_projection, 1, GL_FALSE, view_projection.data());
  glProgramUniformMatrix4fv(p, overlay.model, 1, GL_FALSE, identity.data());
  glUseProgram(p);
  glBindVertexArray(vertex_array_.get());
  glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(staging_.size()));
}

}  // namespace deixis::render
