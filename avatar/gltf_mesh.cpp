#include "avatar/gltf_mesh.h"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "avatar/gltf_accessors.h"
#include "avatar/gltf_limits.h"
#include "avatar/influences.h"
#include "core/error.h"

namespace deixis::avatar::gltf {

namespace {

using Vec3d = Eigen::Vector3d;
using Mat3d = Eigen::Matrix3d;

// How one mesh node's vertices reach the file's model frame.
struct Binding {
  int skin = -1;                // −1: rigid
  std::vector<Mat4d> matrices;  // skinned: T_file_joint · inverse bind, per skin joint
  std::vector<int> joint;       // skinned: skeleton joint per skin joint
  Mat4d rigid = Mat4d::Identity();
  int rigid_joint = 0;
};

struct Context {
  const tinygltf::Model& model;
  const Mat3d& R_model_file;
  const std::string& source;
};

Binding skinned_binding(const Context& c, const NodeTree& tree, const JointNodes& joints,
                        int skin_index) {
  const tinygltf::Model& m = c.model;
  const std::string where = c.source + ": skins[" + std::to_string(skin_index) + "]";
  if (static_cast<std::size_t>(skin_index) >= m.skins.size()) {
    throw Error(where + " does not exist (the file has " + std::to_string(m.skins.size()) +
                " skins)");
  }
  const tinygltf::Skin& skin = m.skins[skin_index];
  Binding b;
  b.skin = skin_index;
  std::vector<float> inverse_binds;
  if (skin.inverseBindMatrices >= 0) {
    inverse_binds = read_floats({m, where + " inverseBindMatrices"}, skin.inverseBindMatrices,
                                TINYGLTF_TYPE_MAT4, 16);
    if (inverse_binds.size() / 16 < skin.joints.size()) {
      throw Error(where + ": " + std::to_string(inverse_binds.size() / 16) +
                  " inverse bind matrices for " + std::to_string(skin.joints.size()) + " joints");
    }
  }
  for (std::size_t k = 0; k < skin.joints.size(); ++k) {
    Mat4d inverse_bind = Mat4d::Identity();
    if (!inverse_binds.empty()) {
      for (int e = 0; e < 16; ++e) {
        inverse_bind(e % 4, e / 4) = inverse_binds[k * 16 + static_cast<std::size_t>(e)];
      }
    }
    const int node = skin.joints[k];
    b.matrices.push_back(tree.global[node] * inverse_bind);
    b.joint.push_back(joints.joint_of_node[node]);
  }
  return b;
}

Binding rigid_binding(const NodeTree& tree, const JointNodes& joints, int node) {
  Binding b;
  b.rigid = tree.global[node];
  for (int a = node; a != -1; a = tree.parent[a]) {
    if (joints.joint_of_node[a] != -1) {
      b.rigid_joint = joints.joint_of_node[a];
      break;
    }
  }
  return b;
}

// Triangle lists from lists, strips and fans; points and lines are not surfaces (empty).
std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& v,
                                     const std::string& where) {
  std::vector<std::uint32_t> t;
  switch (mode) {
    case TINYGLTF_MODE_TRIANGLES:
      if (v.size() % 3 != 0) {
        throw Error(where + ": " + std::to_string(v.size()) +
                    " indices do not make whole triangles");
      }
      return v;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
      for (std::size_t i = 0; i + 2 < v.size(); ++i) {
        const bool even = i % 2 == 0;
        t.insert(t.end(), {v[even ? i : i + 1], v[even ? i + 1 : i], v[i + 2]});
      }
      return t;
    case TINYGLTF_MODE_TRIANGLE_FAN:
      for (std::size_t i = 1; i + 1 < v.size(); ++i) {
        t.insert(t.end(), {v[0], v[i], v[i + 1]});
      }
      return t;
    default:
      return t;
  }
}

std::array<float, 4> base_color(const tinygltf::Model& m, int material) {
  std::array<float, 4> color = {1.0f, 1.0f, 1.0f, 1.0f};
  if (material < 0 || static_cast<std::size_t>(material) >= m.materials.size()) {
    return color;
  }
  const auto& factor = m.materials[material].pbrMetallicRoughness.baseColorFactor;
  if (factor.size() == 4) {
    for (std::size_t k = 0; k < 4; ++k) {
      const double f = factor[k];
      color[k] = std::isfinite(f) ? static_cast<float>(std::clamp(f, 0.0, 1.0)) : 1.0f;
    }
  }
  return color;
}

// The influences of every vertex from JOINTS_n/WEIGHTS_n, n = 0, 1, ... (skin-local joints).
std::vector<std::vector<Influence>> read_influences(const Context& c, const tinygltf::Primitive& p,
                                                    std::size_t vertices, std::size_t skin_joints,
                                                    const std::string& where) {
  std::vector<std::vector<Influence>> influences(vertices);
  for (int set = 0;; ++set) {
    const std::string joints_name = "JOINTS_" + std::to_string(set);
    const std::string weights_name = "WEIGHTS_" + std::to_string(set);
    const auto j = p.attributes.find(joints_name);
    const auto w = p.attributes.find(weights_name);
    if (j == p.attributes.end() && w == p.attributes.end()) {
      if (set == 0) {
        throw Error(where + ": the mesh is skinned but has no JOINTS_0/WEIGHTS_0");
      }
      break;
    }
    if (set == kMaxInfluenceSets) {
      // Each set is read for every vertex and kept until packing: their number is bounded.
      throw Error(where + ": more than " + std::to_string(kMaxInfluenceSets) +
                  " JOINTS_n/WEIGHTS_n sets");
    }
    if (j == p.attributes.end() || w == p.attributes.end()) {
      throw Error(where + ": " + (j == p.attributes.end() ? joints_name : weights_name) +
                  " is missing (JOINTS_n and WEIGHTS_n come in pairs)");
    }
    const auto joint =
        read_uints({c.model, where + " " + joints_name}, j->second, TINYGLTF_TYPE_VEC4, 4);
    const auto weight =
        read_floats({c.model, where + " " + weights_name}, w->second, TINYGLTF_TYPE_VEC4, 4);
    if (joint.size() != 4 * vertices || weight.size() != 4 * vertices) {
      throw Error(where + ": " + joints_name + "/" + weights_name + " have " +
                  std::to_string(joint.size() / 4) + "/" + std::to_string(weight.size() / 4) +
                  " elements for " + std::to_string(vertices) + " vertices");
    }
    for (std::size_t i = 0; i < 4 * vertices; ++i) {
      if (weight[i] < 0.0f) {
        throw Error(where + ": vertex " + std::to_string(i / 4) + ": negative skin weight");
      }
      if (weight[i] > 0.0f && joint[i] >= skin_joints) {
        throw Error(where + ": vertex " + std::to_string(i / 4) + ": joint " +
                    std::to_string(joint[i]) + " is not in its skin (" +
                    std::to_string(skin_joints) + " joints)");
      }
      influences[i / 4].push_back({static_cast<int>(joint[i]), weight[i]});
    }
  }
  return influences;
}

Vec3 to_model(const Mat3d& R, const Vec3d& v) {
  return (R * v).cast<float>();
}

// Normals from the triangles (area-weighted), for primitives without NORMAL.
void compute_normals(SkinnedMesh& mesh, std::size_t first_vertex, std::size_t first_index) {
  for (std::size_t v = first_vertex; v < mesh.positions.size(); ++v) {
    mesh.normals[v] = Vec3::Zero();
  }
  for (std::size_t i = first_index; i + 2 < mesh.indices.size(); i += 3) {
    const Vec3& a = mesh.positions[mesh.indices[i]];
    const Vec3 n =
        (mesh.positions[mesh.indices[i + 1]] - a).cross(mesh.positions[mesh.indices[i + 2]] - a);
    for (int k = 0; k < 3; ++k) {
      mesh.normals[mesh.indices[i + static_cast<std::size_t>(k)]] += n;
    }
  }
  for (std::size_t v = first_vertex; v < mesh.positions.size(); ++v) {
    const float length = mesh.normals[v].norm();
    mesh.normals[v] = length > 0.0f ? Vec3(mesh.normals[v] / length) : Vec3(Vec3::UnitY());
  }
}

// Primitives of one mesh node that list the same attribute accessors share their vertices (the
// generated avatar does this); each set is baked once. Key: the attributes, value: first vertex.
using SharedVertices = std::map<std::map<std::string, int>, std::size_t>;

void add_triangles(const Context& c, const tinygltf::Primitive& p, std::size_t first_vertex,
                   const std::vector<std::uint32_t>& indices, SkinnedMesh& out) {
  SkinnedPrimitive primitive;
  if (p.material >= 0 && static_cast<std::size_t>(p.material) < c.model.materials.size()) {
    primitive.name = c.model.materials[p.material].name;
  }
  primitive.first_index = static_cast<std::uint32_t>(out.indices.size());
  for (const std::uint32_t i : indices) {
    out.indices.push_back(static_cast<std::uint32_t>(first_vertex) + i);
  }
  primitive.index_count = static_cast<std::uint32_t>(out.indices.size() - primitive.first_index);
  primitive.base_color = base_color(c.model, p.material);
  out.primitives.push_back(std::move(primitive));
}

void add_primitive(const Context& c, const Binding& b, int mesh_index, int primitive_index,
                   SharedVertices& shared, SkinnedMesh& out) {
  const tinygltf::Primitive& p = c.model.meshes[mesh_index].primitives[primitive_index];
  const std::string where = c.source + ": meshes[" + std::to_string(mesh_index) + "].primitives[" +
                            std::to_string(primitive_index) + "]";
  const auto position = p.attributes.find("POSITION");
  if (position == p.attributes.end()) {
    throw Error(where + ": no POSITION attribute");
  }
  const auto xyz =
      read_floats({c.model, where + " POSITION"}, position->second, TINYGLTF_TYPE_VEC3, 3);
  const std::size_t n = xyz.size() / 3;
  std::vector<float> normal;
  if (const auto it = p.attributes.find("NORMAL"); it != p.attributes.end()) {
    normal = read_floats({c.model, where + " NORMAL"}, it->second, TINYGLTF_TYPE_VEC3, 3);
    if (normal.size() != xyz.size()) {
      throw Error(where + ": NORMAL has " + std::to_string(normal.size() / 3) + " elements for " +
                  std::to_string(n) + " vertices");
    }
  }
  std::vector<std::uint32_t> indices;
  if (p.indices >= 0) {
    indices = read_uints({c.model, where + " indices"}, p.indices, TINYGLTF_TYPE_SCALAR, 1);
  } else {
    indices.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      indices[i] = static_cast<std::uint32_t>(i);
    }
  }
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= n) {
      throw Error(where + ": index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                  ", past the " + std::to_string(n) + " vertices");
    }
  }
  indices = triangles(p.mode, indices, where);
  if (indices.empty()) {
    return;  // points or lines
  }
  if (const auto it = shared.find(p.attributes); it != shared.end()) {
    add_triangles(c, p, it->second, indices, out);
    return;
  }
  std::vector<std::vector<Influence>> influences;
  if (b.skin >= 0) {
    influences = read_influences(c, p, n, b.matrices.size(), where);
  }

  const std::size_t first_vertex = out.positions.size();
  const std::size_t first_index = out.indices.size();
  for (std::size_t v = 0; v < n; ++v) {
    PackedInfluences packed;
    Mat4d M = b.rigid;
    if (b.skin >= 0) {
      if (!pack_influences(influences[v], packed)) {
        throw Error(where + ": vertex " + std::to_string(v) + ": skin weights sum to zero");
      }
      M.setZero();
      for (int k = 0; k < kMaxInfluences; ++k) {
        std::uint16_t& joint = packed.joints[k];  // skin-local here, the skeleton's after
        if (packed.weights[k] > 0.0f) {
          M += static_cast<double>(packed.weights[k]) * b.matrices[joint];
          joint = static_cast<std::uint16_t>(b.joint[joint]);
        } else {
          joint = 0;
        }
      }
    } else {
      packed.joints[0] = static_cast<std::uint16_t>(b.rigid_joint);
      packed.weights[0] = 1.0f;
    }
    const Vec3d x(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    out.positions.push_back(to_model(c.R_model_file, (M * x.homogeneous()).head<3>()));
    if (!out.positions.back().allFinite()) {
      throw Error(where + ": vertex " + std::to_string(v) + ": rest position is not finite");
    }
    Vec3 nv = Vec3::UnitY();
    if (!normal.empty()) {
      // Normals transform by the inverse transpose of the linear part.
      const Mat3d L = M.topLeftCorner<3, 3>();
      const Mat3d N = std::abs(L.determinant()) > 1e-12 ? Mat3d(L.inverse().transpose()) : L;
      const Vec3 t =
          to_model(c.R_model_file, N * Vec3d(normal[3 * v], normal[3 * v + 1], normal[3 * v + 2]));
      nv = t.norm() > 0.0f && t.allFinite() ? Vec3(t.normalized()) : Vec3(Vec3::UnitY());
    }
    out.normals.push_back(nv);
    out.joints.push_back(packed.joints);
    out.weights.push_back(packed.weights);
  }
  add_triangles(c, p, first_vertex, indices, out);
  if (normal.empty()) {
    compute_normals(out, first_vertex, first_index);  // from this primitive's triangles only
  } else {
    shared[p.attributes] = first_vertex;
  }
}

}  // namespace

SkinnedMesh bake_rest_mesh(const tinygltf::Model& model, const NodeTree& tree,
                           const JointNodes& joints, const Mat3d& R_model_file,
                           const std::string& source) {
  const Context c{model, R_model_file, source};
  SkinnedMesh mesh;
  for (const int node : tree.depth_first) {
    const tinygltf::Node& n = model.nodes[node];
    if (n.mesh < 0) {
      continue;
    }
    if (static_cast<std::size_t>(n.mesh) >= model.meshes.size()) {
      throw Error(source + ": " + node_label(model, node) + ": mesh " + std::to_string(n.mesh) +
                  " does not exist");
    }
    // glTF: a skinned mesh ignores its own node's transform; the joints place it.
    const Binding b =
        n.skin >= 0 ? skinned_binding(c, tree, joints, n.skin) : rigid_binding(tree, joints, node);
    SharedVertices shared;
    for (std::size_t p = 0; p < model.meshes[n.mesh].primitives.size(); ++p) {
      add_primitive(c, b, n.mesh, static_cast<int>(p), shared, mesh);
    }
  }
  return mesh;
}

}  // namespace deixis::avatar::gltf
