#pragma once
// What one frame shows, as plain data the caller fills every frame: the camera, the avatars with
// their current skeleton poses, and debug lines. The room's target objects change rarely and are
// handed to the renderer separately (Renderer::set_targets). Nothing here knows where the poses
// came from: interpolating between 30 Hz ticks is the caller's (render/pose_blend.h helps).

#include <span>
#include <string_view>

#include "core/target_map.h"
#include "render/camera.h"
#include "render/skinned_mesh.h"

namespace deixis::render {

// A skinned mesh uploaded with Renderer::add_skinned_mesh.
struct SkinnedMeshId {
  int index = -1;
};

struct AvatarDraw {
  SkinnedMeshId mesh;
  Pose T_world_model;                   // where the avatar's model frame is in the room
  std::span<const Pose> T_model_joint;  // one per skeleton joint (ik::local_to_model)
  // 1: opaque. Below 1 the avatar is blended over what is behind it (a remote person's avatar
  // fading in or out, site/remote_people.h), its own nearest surface only.
  float opacity = 1.0f;
};

struct DebugLine {  // e.g. the eye–fingertip ray
  Vec3 from = Vec3::Zero();
  Vec3 to = Vec3::Zero();
  Colour colour = Colour(1.0f, 0.9f, 0.1f, 1.0f);
};

// Lines of text fixed in front of the viewer (a headset's head-locked panel, docs/xr.md
// "Presence panel"): the caller places it each frame from the head's pose; it is drawn over
// everything else, left-aligned, each line on a dark plate.
struct HeadPanel {
  Pose T_world_panel;  // its centre; lines in its x-y plane (x right, y up), read from +z
  std::span<const std::string_view> lines;  // top first; at most PanelPass::kMaxLines
  float line_height = 0.016f;               // m per line, plate included
};

struct SceneView {
  Camera camera;
  std::span<const AvatarDraw> avatars;
  std::span<const DebugLine> lines;
  bool show_floor = true;
  bool show_targets = true;
  bool show_labels = true;           // the targets' names
  const HeadPanel* panel = nullptr;  // drawn over everything when set
};

struct RendererOptions {
  Colour background = Colour(0.62f, 0.72f, 0.82f, 1.0f);  // alpha 0: see-through (xr/blend_mode.h)
  Colour floor_colour = Colour(0.45f, 0.46f, 0.47f, 1.0f);
  Colour grid_colour = Colour(0.28f, 0.29f, 0.30f, 1.0f);
  float floor_height = 0.0f;                                    // m, world y of the floor
  float floor_extent = 25.0f;                                   // m, half the floor square's side
  float grid_spacing = 0.5f;                                    // m
  Vec3 light_direction = Vec3(0.35f, 1.0f, 0.6f).normalized();  // towards the light
  float ambient = 0.35f;
  float label_height = 0.12f;  // m, a label's plate in the world
  float label_gap = 0.05f;     // m, between an object's top and its label
  Colour label_text = Colour(1.0f, 1.0f, 1.0f, 1.0f);
  Colour label_backing = Colour(0.05f, 0.05f, 0.06f, 0.75f);
};

// The colour every renderer draws target `id` in (a fixed palette by id, so both sites and the
// tests agree); id 0, the partner, is grey.
Colour target_colour(TargetId id);

}  // namespace deixis::render
