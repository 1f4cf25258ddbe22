#include "render/renderer.h"

namespace deixis::render {
namespace {

// Everything the passes rely on, set explicitly: the context may come from a UI or an XR
// runtime that left other state behind.
void begin_frame(const RenderTarget& target, const RendererOptions& options) {
  glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
  glViewport(0, 0, target.width, target.height);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_BLEND);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glClearColor(options.background.x(), options.background.y(), options.background.z(),
               options.background.w());
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

// Checked before any member compiles a shader, so an old context is named as such rather than
// reported as a failed "#version 450" compile.
const RendererOptions& require_gl45(const RendererOptions& options) {
  require_gl_version(4, 5, "renderer");
  return options;
}

void end_frame() {
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glBindVertexArray(0);
  glUseProgram(0);
}

}  // namespace

Renderer::Renderer(const RendererOptions& options)
    : options_(require_gl45(options)), overlay_(overlay_program()) {
  check_gl("renderer set-up");
}

SkinnedMeshId Renderer::add_skinned_mesh(const SkinnedMesh& mesh) {
  return avatars_.add(mesh);
}

void Renderer::set_targets(const TargetMap& map) {
  targets_.set_targets(map, options_);
}

bool Renderer::move_target(TargetId id, const Vec3& position) {
  return targets_.move_target(id, position);
}

void Renderer::render(const SceneView& view, const RenderTarget& target) {
  const Camera& camera = view.camera;
  const Mat4 view_projection =
      projection_matrix(camera.fov, camera.near_distance, camera.far_distance) *
      view_matrix(camera);
  begin_frame(target, options_);
  if (view.show_floor) {
    floor_.draw(view_projection, camera.T_world_eye.translation, options_);
  }
  if (view.show_targets) {
    targets_.draw_objects(view_projection, options_);
  }
  avatars_.draw(view.avatars, view_projection, options_);
  glDisable(GL_CULL_FACE);
  lines_.draw(view.lines, view_projection, overlay_);
  if (view.show_targets && view.show_labels) {
    // Labels are see-through plates: blended, tested against the scene's depth but not writing
    // it, drawn plate first and glyphs second.
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    targets_.draw_labels(camera, view_projection, overlay_, options_);
  }
  if (view.panel != nullptr) {
    // Over everything; colour blended over the scene, alpha accumulated, so a see-through
    // layer's premultiplied alpha stays right where the plates are.
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    panel_.draw(*view.panel, view_projection, overlay_, options_);
    glEnable(GL_DEPTH_TEST);
  }
  end_frame();
}

}  // namespace deixis::render
