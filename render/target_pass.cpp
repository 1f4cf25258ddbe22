#include "render/target_pass.h"

#include "render/primitives.h"

namespace deixis::render {

Colour target_colour(TargetId id) {
  static constexpr float kPalette[][3] = {
      {0.85f, 0.22f, 0.18f},  // red
      {0.18f, 0.48f, 0.90f},  // blue
      {0.22f, 0.72f, 0.28f},  // green
      {0.95f, 0.76f, 0.15f},  // yellow
      {0.62f, 0.32f, 0.85f},  // purple
      {0.15f, 0.78f, 0.78f},  // cyan
      {0.95f, 0.50f, 0.12f},  // orange
      {0.90f, 0.38f, 0.65f},  // pink
  };
  if (id <= 0) {
    return {0.6f, 0.6f, 0.6f, 1.0f};
  }
  const auto& c = kPalette[static_cast<std::size_t>(id - 1) % std::size(kPalette)];
  return {c[0], c[1], c[2], 1.0f};
}

TargetPass::TargetPass()
    : lit_(lit_program(false, 0)),
      sphere_(upload(unit_sphere(16, 32))),
      cube_(upload(unit_cube())),
      label_vertices_(create_buffer()),
      label_array_(overlay_vertex_array(label_vertices_.get())) {}

void TargetPass::set_targets(const TargetMap& map, const RendererOptions& options) {
  targets_.clear();
  std::vector<OverlayVertex> vertices;
  for (const TargetObject& object : map.objects) {
    Target t;
    t.id = object.id;
    t.kind = object.kind;
    const Vec3 size = object.size.cwiseMax(Vec3::Constant(1e-4f));
    t.model = Mat4::Identity();
    t.model.topLeftCorner<3, 3>() = size.asDiagonal();
    t.model.topRightCorner<3, 1>() = object.position;
    t.normal_matrix = size.cwiseInverse().asDiagonal();
    t.colour = target_colour(object.id);
    t.label_anchor = object.position + Vec3(0.0f, 0.5f * size.y() + options.label_gap, 0.0f);
    t.label = append_label(object.name, options.label_text, options.label_backing, vertices);
    targets_.push_back(t);
  }
  glNamedBufferData(label_vertices_.get(),
                    static_cast<GLsizeiptr>(vertices.size() * sizeof(OverlayVertex)),
                    vertices.empty() ? nullptr : vertices.data(), GL_STATIC_DRAW);
}

bool TargetPass::move_target(TargetId id, const Vec3& position) {
  for (Target& t : targets_) {
    if (t.id == id) {
      const Vec3 shift = position - t.model.topRightCorner<3, 1>();
      t.model.topRightCorner<3, 1>() = position;
      t.label_anchor += shift;
      return true;
    }
  }
  return false;
}

void TargetPass::draw_objects(const Mat4& view_projection, const RendererOptions& options) const {
  const GLuint p = lit_.program.id();
  set_frame_uniforms(lit_, view_projection, options);
  glUseProgram(p);
  glEnable(GL_CULL_FACE);
  for (const Target& t : targets_) {
    const GpuMesh& mesh = t.kind == TargetKind::kSphere ? sphere_ : cube_;
    glProgramUniformMatrix4fv(p, lit_.model, 1, GL_FALSE, t.model.data());
    glProgramUniformMatrix3fv(p, lit_.normal_matrix, 1, GL_FALSE, t.normal_matrix.data());
    glProgramUniform4fv(p, lit_.colour, 1, t.colour.data());
    glBindVertexArray(mesh.vertex_array.get());
    glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
  }
}

void TargetPass::draw_labels(const Camera& camera, const Mat4& view_projection,
                             const OverlayProgram& overlay, const RendererOptions& options) const {
  if (targets_.empty()) {
    return;
  }
  const GLuint p = overlay.program.id();
  glProgramUniformMatrix4fv(p, overlay.view_projection, 1, GL_FALSE, view_projection.data());
  glUseProgram(p);
  glBindVertexArray(label_array_.get());
  // A billboard: label space's x and y along the eye's right and up, so every label faces the
  // camera (each eye's own in XR) and reads left to right.
  const Mat3& R_world_eye = camera.T_world_eye.rotation;
  for (const Target& t : targets_) {
    const float scale = options.label_height / std::max(t.label.height, 1.0f);
    Mat4 model = Mat4::Identity();
    model.topLeftCorner<3, 3>() = R_world_eye * scale;
    model.topRightCorner<3, 1>() = t.label_anchor;
    glProgramUniformMatrix4fv(p, overlay.model, 1, GL_FALSE, model.data());
    glDrawArrays(GL_TRIANGLES, t.label.first, t.label.count);
  }
}

}  // namespace deixis::render
