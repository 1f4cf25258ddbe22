#pragma once
// The room's target objects (spheres, boxes, screens) in their palette colours, and their names
// as labels: billboards facing the camera above each object, drawn after everything opaque.

#include <vector>

#include "core/target_map.h"
#include "render/gpu_mesh.h"
#include "render/label_text.h"
#include "render/programs.h"

namespace deixis::render {

class TargetPass {
 public:
  TargetPass();
  // Rebuilds the per-object transforms and the label geometry (allocates; call on map changes).
  void set_targets(const TargetMap& map, const RendererOptions& options);
  // Moves object `id` (its centre) without rebuilding anything: no allocation, so an object can
  // follow the mouse every frame. Returns false when no object has that id.
  bool move_target(TargetId id, const Vec3& position);
  void draw_objects(const Mat4& view_projection, const RendererOptions& options) const;
  void draw_labels(const Camera& camera, const Mat4& view_projection, const OverlayProgram& overlay,
                   const RendererOptions& options) const;

 private:
  struct Target {
    TargetId id = kNoTarget;
    TargetKind kind = TargetKind::kSphere;
    Mat4 model;
    Eigen::Matrix3f normal_matrix;
    Colour colour;
    Vec3 label_anchor;  // bottom centre of the label, world frame
    LabelExtent label;
  };

  LitProgram lit_;
  GpuMesh sphere_;
  GpuMesh cube_;
  std::vector<Target> targets_;
  GlBuffer label_vertices_;
  GlVertexArray label_array_;
};

}  // namespace deixis::render
