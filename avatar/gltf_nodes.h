#pragma once
// The node hierarchy of a glTF file (internal to the avatar loader): parents, a depth-first order,
// and every node's transform in the file's model frame, after checking that the nodes form a
// forest and every transform is finite. Then the subset of nodes that becomes the avatar's
// skeleton.

#include <tiny_gltf.h>

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

namespace deixis::avatar::gltf {

using Mat4d = Eigen::Matrix4d;

struct NodeTree {
  std::vector<int> parent;       // −1 for a root
  std::vector<int> depth_first;  // every node once, each after its parent, children in file order
  std::vector<Mat4d> global;     // T_file_node, scale included
};

// "nodes[12] 'leftHand'", for error messages.
std::string node_label(const tinygltf::Model& model, int node);

// Throws deixis::Error naming `source` and the node when a child index is out of range, a node has
// two parents or lies on a cycle, or a transform is malformed or not finite in float.
NodeTree read_node_tree(const tinygltf::Model& model, const std::string& source);

// The skeleton's nodes: every node in `marked` (the skins' joints, humanoid bones named by a VRM
// extension) plus the nodes between a marked node and its nearest marked ancestor, so the
// skeleton is connected wherever the file's hierarchy is. In depth-first order, with each joint's
// parent the nearest ancestor that is also a joint.
struct JointNodes {
  std::vector<int> node;           // per joint
  std::vector<int> parent_joint;   // per joint, −1 for a root
  std::vector<int> joint_of_node;  // per node, −1 when not a joint
};
JointNodes select_joint_nodes(const NodeTree& tree, std::span<const int> marked);

}  // namespace deixis::avatar::gltf
