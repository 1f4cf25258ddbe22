#pragma once
// Meshes uploaded to the GPU once, at load: interleaved vertices, triangle indices and a vertex
// array that describes them to the shaders of shaders/mesh.vert (attribute 0 position, 1 normal,
// and for skinned meshes 2 joints, 3 weights) or shaders/overlay.vert (0 position, 1 colour).

#include <vector>

#include "render/gl_object.h"
#include "render/skinned_mesh.h"

namespace deixis::render {

struct GpuMesh {
  GlVertexArray vertex_array;
  GlBuffer vertices;
  GlBuffer indices;
  GLsizei index_count = 0;
};

// A skinned mesh on the GPU, with what drawing needs from its source on the CPU.
struct GpuSkinnedMesh {
  GpuMesh geometry;
  std::vector<SkinnedPrimitive> primitives;
  std::vector<Pose> inverse_bind;
};

GpuMesh upload(const StaticMesh& mesh);

// Validates (render/skinned_mesh.h, validate) and uploads; joint slots whose weight is zero are
// sent as joint 0 so the shader never reads past the joint array.
GpuSkinnedMesh upload(const SkinnedMesh& mesh, int max_joints);

// A vertex of the unlit overlay (labels and debug lines), world or label space.
struct OverlayVertex {
  float position[3];
  float colour[4];
};

// A vertex array over `buffer` holding OverlayVertex records.
GlVertexArray overlay_vertex_array(GLuint buffer);

}  // namespace deixis::render
