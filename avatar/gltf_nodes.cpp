#include "avatar/gltf_nodes.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace deixis::avatar::gltf {

namespace {

constexpr double kFloatMax = std::numeric_limits<float>::max();

// Finite and representable as float (a value that overflows float is as unusable as an infinity).
bool finite_in_float(double v) {
  return std::isfinite(v) && std::abs(v) <= kFloatMax;
}

bool all_finite_in_float(const std::vector<double>& values) {
  for (const double v : values) {
    if (!finite_in_float(v)) {
      return false;
    }
  }
  return true;
}

Mat4d local_transform(const tinygltf::Model& model, int i, const std::string& source) {
  const tinygltf::Node& n = model.nodes[i];
  const auto fail = [&](const std::string& what) {
    throw Error(source + ": " + node_label(model, i) + ": " + what);
  };
  Mat4d T = Mat4d::Identity();
  if (!n.matrix.empty()) {
    if (n.matrix.size() != 16) {
      fail("matrix has " + std::to_string(n.matrix.size()) + " numbers (expected 16)");
    }
    if (!all_finite_in_float(n.matrix)) {
      fail("non-finite transform (matrix)");
    }
    for (int k = 0; k < 16; ++k) {
      T(k % 4, k / 4) = n.matrix[k];  // column-major
    }
    return T;
  }
  if (!n.translation.empty() && n.translation.size() != 3) {
    fail("translation has " + std::to_string(n.translation.size()) + " numbers (expected 3)");
  }
  if (!n.rotation.empty() && n.rotation.size() != 4) {
    fail("rotation has " + std::to_string(n.rotation.size()) + " numbers (expected 4)");
  }
  if (!n.scale.empty() && n.scale.size() != 3) {
    fail("scale has " + std::to_string(n.scale.size()) + " numbers (expected 3)");
  }
  if (!all_finite_in_float(n.translation) || !all_finite_in_float(n.rotation) ||
      !all_finite_in_float(n.scale)) {
    fail("non-finite transform (translation, rotation or scale)");
  }
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (!n.rotation.empty()) {
    Eigen::Quaterniond q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (q.norm() < 1e-6) {
      fail("rotation quaternion has zero length");
    }
    R = q.normalized().toRotationMatrix();
  }
  Eigen::Vector3d s = Eigen::Vector3d::Ones();
  if (!n.scale.empty()) {
    s = Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]);
  }
  T.topLeftCorner<3, 3>() = R * s.asDiagonal();
  if (!n.translation.empty()) {
    T.topRightCorner<3, 1>() =
        Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]);
  }
  return T;
}

bool finite_in_float(const Mat4d& T) {
  for (int k = 0; k < 16; ++k) {
    if (!finite_in_float(T(k % 4, k / 4))) {
      return false;
    }
  }
  return true;
}

}  // namespace

std::string node_label(const tinygltf::Model& model, int node) {
  std::string label = "nodes[" + std::to_string(node) + "]";
  if (node >= 0 && static_cast<std::size_t>(node) < model.nodes.size() &&
      !model.nodes[node].name.empty()) {
    label += " '" + model.nodes[node].name + "'";
  }
  return label;
}

NodeTree read_node_tree(const tinygltf::Model& model, const std::string& source) {
  const int n = static_cast<int>(model.nodes.size());
  NodeTree tree;
  tree.parent.assign(n, -1);
  for (int i = 0; i < n; ++i) {
    for (const int child : model.nodes[i].children) {
      if (child < 0 || child >= n) {
        throw Error(source + ": " + node_label(model, i) + ": child " + std::to_string(child) +
                    " does not exist (the file has " + std::to_string(n) + " nodes)");
      }
      if (child == i || tree.parent[child] != -1) {
        throw Error(source + ": " + node_label(model, child) +
                    " has more than one parent (the node hierarchy must be a tree)");
      }
      tree.parent[child] = i;
    }
  }
  tree.global.assign(n, Mat4d::Identity());
  std::vector<int> stack;
  for (int root = n - 1; root >= 0; --root) {
    if (tree.parent[root] == -1) {
      stack.push_back(root);
    }
  }
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    tree.depth_first.push_back(i);
    const Mat4d local = local_transform(model, i, source);
    tree.global[i] = tree.parent[i] == -1 ? local : Mat4d(tree.global[tree.parent[i]] * local);
    if (!finite_in_float(tree.global[i])) {
      throw Error(source + ": " + node_label(model, i) +
                  ": non-finite transform (its model transform overflows)");
    }
    const auto& children = model.nodes[i].children;
    for (auto c = children.rbegin(); c != children.rend(); ++c) {
      stack.push_back(*c);
    }
  }
  // Every node has at most one parent, so a node no root reaches lies on a cycle.
  if (static_cast<int>(tree.depth_first.size()) != n) {
    std::vector<bool> reached(n, false);
    for (const int i : tree.depth_first) {
      reached[i] = true;
    }
    int first = 0;
    while (reached[first]) {
      ++first;
    }
    throw Error(source + ": " + node_label(model, first) +
                " lies on a cycle (the node hierarchy must be a tree)");
  }
  return tree;
}

JointNodes select_joint_nodes(const NodeTree& tree, std::span<const int> marked) {
  const int n = static_cast<int>(tree.parent.size());
  std::vector<bool> is_joint(n, false);
  for (const int m : marked) {
    is_joint[m] = true;
  }
  // Nodes strictly between a marked node and its nearest marked ancestor join the skeleton.
  const std::vector<bool> marked_only = is_joint;
  std::vector<int> path;
  for (int i = 0; i < n; ++i) {
    if (!marked_only[i]) {
      continue;
    }
    path.clear();
    int a = tree.parent[i];
    while (a != -1 && !marked_only[a]) {
      path.push_back(a);
      a = tree.parent[a];
    }
    if (a != -1) {
      for (const int p : path) {
        is_joint[p] = true;
      }
    }
  }
  JointNodes joints;
  joints.joint_of_node.assign(n, -1);
  for (const int i : tree.depth_first) {
    if (!is_joint[i]) {
      continue;
    }
    int a = tree.parent[i];
    while (a != -1 && !is_joint[a]) {
      a = tree.parent[a];
    }
    joints.joint_of_node[i] = static_cast<int>(joints.node.size());
    joints.node.push_back(i);
    joints.parent_joint.push_back(a == -1 ? -1 : joints.joint_of_node[a]);
  }
  return joints;
}

}  // namespace deixis::avatar::gltf
