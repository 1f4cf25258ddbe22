#pragma once
// The renderer: draws a SceneView (camera, avatars, debug lines) and the room's target objects
// into a RenderTarget with OpenGL 4.5 core. It knows nothing of networks, windows or XR: the
// headless and window contexts (render/context.h) and the OpenXR front end hand it a target
// and a camera per view.
//
// Needs its context current when constructed, used and destroyed. Every frame sets all the GL
// state it relies on and leaves no program or vertex array bound, so a UI drawn afterwards in the
// same framebuffer (Dear ImGui's OpenGL backend saves and restores its own) works unchanged.

#include "render/avatar_pass.h"
#include "render/floor_pass.h"
#include "render/line_pass.h"
#include "render/panel_pass.h"
#include "render/render_target.h"
#include "render/scene.h"
#include "render/target_pass.h"

namespace deixis::render {

class Renderer {
 public:
  // Compiles the embedded shaders and builds the target primitives. Throws deixis::Error (with
  // the driver's log for a shader) when that fails or the context is older than OpenGL 4.5.
  explicit Renderer(const RendererOptions& options = {});

  // Uploads an avatar's mesh once; draws refer to it by the returned id.
  SkinnedMeshId add_skinned_mesh(const SkinnedMesh& mesh);
  // The room's objects and their names, until the next call.
  void set_targets(const TargetMap& map);
  // Moves one of those objects to a new centre (a dragged object); allocates nothing. False when
  // the map set last has no object `id`.
  bool move_target(TargetId id, const Vec3& position);

  // Draws one view. Throws deixis::Error only for caller mistakes (unknown mesh id, wrong joint
  // count); allocates only when a frame has more avatars or lines than any before it.
  void render(const SceneView& view, const RenderTarget& target);

  const RendererOptions& options() const { return options_; }

 private:
  RendererOptions options_;
  FloorPass floor_;
  TargetPass targets_;
  AvatarPass avatars_;
  OverlayProgram overlay_;
  LinePass lines_;
  PanelPass panel_;
};

}  // namespace deixis::render
