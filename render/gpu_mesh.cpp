#include "render/gpu_mesh.h"

#include <cstddef>

namespace deixis::render {
namespace {

struct StaticVertex {
  float position[3];
  float normal[3];
};

struct SkinnedVertex {
  float position[3];
  float normal[3];
  std::uint16_t joints[4];
  float weights[4];
};

void copy3(float (&out)[3], const Vec3& v) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

template <typename Vertex>
GpuMesh upload_geometry(const std::vector<Vertex>& vertices,
                        const std::vector<std::uint32_t>& indices) {
  GpuMesh mesh;
  mesh.vertices = create_buffer();
  mesh.indices = create_buffer();
  mesh.vertex_array = create_vertex_array();
  mesh.index_count = static_cast<GLsizei>(indices.size());
  glNamedBufferStorage(mesh.vertices.get(),
                       static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)), vertices.data(),
                       0);
  glNamedBufferStorage(mesh.indices.get(),
                       static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                       indices.data(), 0);
  const GLuint vao = mesh.vertex_array.get();
  glVertexArrayVertexBuffer(vao, 0, mesh.vertices.get(), 0, sizeof(Vertex));
  glVertexArrayElementBuffer(vao, mesh.indices.get());
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, position));
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, offsetof(Vertex, normal));
  glVertexArrayAttribBinding(vao, 1, 0);
  return mesh;
}

}  // namespace

GpuMesh upload(const StaticMesh& mesh) {
  std::vector<StaticVertex> vertices(mesh.positions.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    copy3(vertices[i].position, mesh.positions[i]);
    copy3(vertices[i].normal, mesh.normals[i]);
  }
  return upload_geometry(vertices, mesh.indices);
}

GpuSkinnedMesh upload(const SkinnedMesh& mesh, int max_joints) {
  validate(mesh, max_joints, "skinned mesh");
  std::vector<SkinnedVertex> vertices(mesh.positions.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    SkinnedVertex& v = vertices[i];
    copy3(v.position, mesh.positions[i]);
    copy3(v.normal, mesh.normals[i]);
    for (int k = 0; k < 4; ++k) {
      v.weights[k] = mesh.weights[i][k];
      v.joints[k] = v.weights[k] > 0.0f ? mesh.joints[i][k] : std::uint16_t{0};
    }
  }
  GpuSkinnedMesh out;
  out.geometry = upload_geometry(vertices, mesh.indices);
  const GLuint vao = out.geometry.vertex_array.get();
  glEnableVertexArrayAttrib(vao, 2);
  glVertexArrayAttribIFormat(vao, 2, 4, GL_UNSIGNED_SHORT, offsetof(SkinnedVertex, joints));
  glVertexArrayAttribBinding(vao, 2, 0);
  glEnableVertexArrayAttrib(vao, 3);
  glVertexArrayAttribFormat(vao, 3, 4, GL_FLOAT, GL_FALSE, offsetof(SkinnedVertex, weights));
  glVertexArrayAttribBinding(vao, 3, 0);
  out.primitives = mesh.primitives;
  if (out.primitives.empty()) {
    SkinnedPrimitive all;
    all.index_count = static_cast<std::uint32_t>(mesh.indices.size());
    all.base_color = {0.8f, 0.8f, 0.8f, 1.0f};
    out.primitives.push_back(all);
  }
  out.inverse_bind = mesh.inverse_bind;
  return out;
}

GlVertexArray overlay_vertex_array(GLuint buffer) {
  GlVertexArray vertex_array = create_vertex_array();
  const GLuint vao = vertex_array.get();
  glVertexArrayVertexBuffer(vao, 0, buffer, 0, sizeof(OverlayVertex));
  glEnableVertexArrayAttrib(vao, 0);
  glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, offsetof(OverlayVertex, position));
  glVertexArrayAttribBinding(vao, 0, 0);
  glEnableVertexArrayAttrib(vao, 1);
  glVertexArrayAttribFormat(vao, 1, 4, GL_FLOAT, GL_FALSE, offsetof(OverlayVertex, colour));
  glVertexArrayAttribBinding(vao, 1, 0);
  return vertex_array;
}

}  // namespace deixis::render
