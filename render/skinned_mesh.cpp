#include "render/skinned_mesh.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace deixis::render {
namespace {

[[noreturn]] void fail(std::string_view source, const std::string& what) {
  throw Error(std::string(source) + ": " + what);
}

void check_sizes(const SkinnedMesh& mesh, int max_joints, std::string_view source) {
  const std::size_t n = mesh.positions.size();
  if (n == 0 || mesh.indices.empty()) {
    fail(source, "mesh has no vertices or no triangles");
  }
  if (mesh.normals.size() != n || mesh.joints.size() != n || mesh.weights.size() != n) {
    fail(source, std::to_string(n) + " positions but " + std::to_string(mesh.normals.size()) +
                     " normals, " + std::to_string(mesh.joints.size()) + " joint sets and " +
                     std::to_string(mesh.weights.size()) + " weight sets");
  }
  if (mesh.indices.size() % 3 != 0) {
    fail(source, std::to_string(mesh.indices.size()) + " indices, not whole triangles");
  }
  const std::size_t joints = mesh.inverse_bind.size();
  if (joints == 0 || joints > static_cast<std::size_t>(max_joints)) {
    fail(source, std::to_string(joints) + " joints (the renderer draws 1 to " +
                     std::to_string(max_joints) + ")");
  }
}

void check_vertices(const SkinnedMesh& mesh, std::string_view source) {
  const std::size_t joints = mesh.inverse_bind.size();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!mesh.positions[v].allFinite() || !mesh.normals[v].allFinite()) {
      fail(source, "vertex " + std::to_string(v) + " has a non-finite position or normal");
    }
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) {
      const float w = mesh.weights[v][k];
      if (!std::isfinite(w) || w < 0.0f) {
        fail(source, "vertex " + std::to_string(v) + " has weight " + std::to_string(w));
      }
      if (w > 0.0f && mesh.joints[v][k] >= joints) {
        fail(source, "vertex " + std::to_string(v) + " references joint " +
                         std::to_string(mesh.joints[v][k]) + ", but the mesh has " +
                         std::to_string(joints) + " joints");
      }
      sum += w;
    }
    if (std::abs(sum - 1.0f) > 1e-3f) {
      fail(source, "vertex " + std::to_string(v) + "'s weights sum to " + std::to_string(sum) +
                       " (expected 1)");
    }
  }
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) {
    if (mesh.indices[i] >= mesh.positions.size()) {
      fail(source, "index " + std::to_string(i) + " = " + std::to_string(mesh.indices[i]) +
                       " is past the " + std::to_string(mesh.positions.size()) + " vertices");
    }
  }
}

}  // namespace

void validate(const SkinnedMesh& mesh, int max_joints, std::string_view source) {
  check_sizes(mesh, max_joints, source);
  check_vertices(mesh, source);
  for (std::size_t j = 0; j < mesh.inverse_bind.size(); ++j) {
    if (!is_finite(mesh.inverse_bind[j])) {
      fail(source, "inverse bind pose " + std::to_string(j) + " is not finite");
    }
  }
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const SkinnedPrimitive& prim = mesh.primitives[p];
    if (prim.index_count % 3 != 0 ||
        std::size_t{prim.first_index} + prim.index_count > mesh.indices.size()) {
      fail(source, "primitive " + std::to_string(p) + " covers indices " +
                       std::to_string(prim.first_index) + " + " + std::to_string(prim.index_count) +
                       " of " + std::to_string(mesh.indices.size()));
    }
  }
}

}  // namespace deixis::render
