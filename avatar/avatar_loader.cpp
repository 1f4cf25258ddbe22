#include "avatar/avatar_loader.h"

#include <tiny_gltf.h>

#include <Eigen/SVD>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

#include "avatar/bone_mapping.h"
#include "avatar/gltf_limits.h"
#include "avatar/gltf_mesh.h"
#include "avatar/gltf_nodes.h"
#include "avatar/gltf_vrm.h"
#include "avatar/rig_measurements.h"
#include "core/error.h"
#include "core/tracking.h"

namespace deixis::avatar {

namespace {

using Mat3d = Eigen::Matrix3d;
using Vec3d = Eigen::Vector3d;

using gltf::kMaxFileBytes;
constexpr int kMaxJoints = 1024;

// A rigid transform in double precision, for the conversions done once at load.
struct PoseD {
  Mat3d R = Mat3d::Identity();
  Vec3d t = Vec3d::Zero();
};

PoseD compose(const PoseD& a, const PoseD& b) {
  return {a.R * b.R, a.R * b.t + a.t};
}
PoseD inverse(const PoseD& a) {
  return {a.R.transpose(), -(a.R.transpose() * a.t)};
}
Pose to_float(const PoseD& p) {
  return {p.R.cast<float>(), p.t.cast<float>()};
}

// Images are never used (the renderer takes base colours), so they are not decoded.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
  return true;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) {
    s.pop_back();
  }
  return s;
}

tinygltf::Model parse(std::span<const std::uint8_t> bytes, const std::string& source,
                      const std::filesystem::path& base_dir) {
  if (bytes.empty()) {
    throw Error(source + ": the file is empty");
  }
  if (bytes.size() > kMaxFileBytes) {
    throw Error(source + ": " + std::to_string(bytes.size()) + " bytes is more than the " +
                std::to_string(kMaxFileBytes >> 20) + " MiB an avatar may have");
  }
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  // Everything tinygltf would trust is checked first: chunk lengths, JSON depth and size (its
  // value conversion recurses), and the URIs it would open.
  const std::string kind = binary ? "glTF binary (.glb)" : "glTF (.gltf) file";
  gltf::check_gltf_json(gltf::gltf_json(bytes, binary, source), source, !base_dir.empty(), kind);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skip_image, nullptr);
  gltf::ConfinedFiles files(base_dir);  // and, behind that check, it opens nothing else
  loader.SetFsCallbacks(files.callbacks());
  std::string err;
  std::string warn;
  bool ok = false;
  try {
    const auto size = static_cast<unsigned int>(bytes.size());
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size,
                                              base_dir.string())
                : loader.LoadASCIIFromString(&model, &err, &warn,
                                             reinterpret_cast<const char*>(bytes.data()), size,
                                             base_dir.string());
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (!ok) {
    throw Error(source + ": not a readable " + kind + ": " +
                (err.empty() ? "tinygltf gave no reason" : trimmed(err)));
  }
  return model;
}

// The nodes that make up the skeleton: skin joints (checked) and VRM humanoid nodes.
std::vector<int> skeleton_nodes(const tinygltf::Model& model, const std::string& source,
                                const std::optional<gltf::VrmHumanoid>& vrm) {
  if (model.skins.empty()) {
    throw Error(source + ": has no skin (an avatar must be a skinned mesh)");
  }
  bool skinned_mesh = false;
  for (const tinygltf::Node& n : model.nodes) {
    skinned_mesh = skinned_mesh || (n.mesh >= 0 && n.skin >= 0);
  }
  if (!skinned_mesh) {
    throw Error(source + ": has no skinned mesh (no node has both a mesh and a skin)");
  }
  std::vector<int> nodes;
  for (std::size_t s = 0; s < model.skins.size(); ++s) {
    const auto& joints = model.skins[s].joints;
    if (joints.empty() || joints.size() > gltf::kMaxSkinJoints) {
      // Every mesh node bound to a skin computes a matrix per entry: the count is bounded.
      throw Error(source + ": skins[" + std::to_string(s) + "] has " +
                  std::to_string(joints.size()) + " joints (1 to " +
                  std::to_string(gltf::kMaxSkinJoints) + ")");
    }
    for (const int j : joints) {
      if (j < 0 || static_cast<std::size_t>(j) >= model.nodes.size()) {
        throw Error(source + ": skins[" + std::to_string(s) + "]: joint node " + std::to_string(j) +
                    " does not exist");
      }
      nodes.push_back(j);
    }
  }
  if (vrm) {
    for (const auto& [bone, node] : vrm->bones) {
      nodes.push_back(node);
    }
  }
  return nodes;
}

// The nearest rotation to a transform's linear part (polar decomposition), so joints are rigid
// whatever scale the file puts on them.
PoseD rigid_part(const gltf::Mat4d& T, const tinygltf::Model& model, int node,
                 const std::string& source) {
  const Mat3d A = T.topLeftCorner<3, 3>();
  const Eigen::JacobiSVD<Mat3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Vec3d s = svd.singularValues();
  if (!(A.determinant() > 0.0) || s.minCoeff() <= 1e-9 * s.maxCoeff()) {
    throw Error(source + ": " + gltf::node_label(model, node) +
                ": mirrored or degenerate transform (determinant " +
                std::to_string(A.determinant()) + ")");
  }
  return {svd.matrixU() * svd.matrixV().transpose(), T.topRightCorner<3, 1>()};
}

// The turn about +Y, a multiple of 90°, that puts the avatar's right shoulder at +X (so it faces
// −Z): π for a glTF-conformant file.
double facing_turn(const Vec3d& left_upper_arm, const Vec3d& right_upper_arm,
                   const std::string& source) {
  const Vec3d right = right_upper_arm - left_upper_arm;
  if (std::hypot(right.x(), right.z()) < 1e-6) {
    throw Error(source +
                ": the left and right upper arms are at the same place seen from above; "
                "cannot tell which way the avatar faces");
  }
  const double quarter = std::numbers::pi / 2.0;
  const long k = std::lround(std::atan2(right.z(), right.x()) / quarter);
  const long m = ((k % 4) + 4) % 4;  // 0, 90, 180 or 270 degrees
  return m == 3 ? -quarter : static_cast<double>(m) * quarter;
}

Mat3d yaw(double angle) {
  // Exact for the multiples of 90° used here.
  const double c = std::round(std::cos(angle) * 1e12) / 1e12;
  const double s = std::round(std::sin(angle) * 1e12) / 1e12;
  Mat3d R;
  R << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  return R;
}

BoneMapping map_bones(const ik::Skeleton& skeleton, const gltf::JointNodes& joints,
                      const std::optional<gltf::VrmHumanoid>& vrm, const std::string& source) {
  BoneMapping mapping;
  if (vrm) {
    mapping.source = vrm->source;
    for (const auto& [bone, node] : vrm->bones) {
      mapping.joint[static_cast<int>(bone)] = joints.joint_of_node[node];
    }
  } else {
    mapping = map_bones_by_name(skeleton, source);
  }
  check_bone_mapping(mapping, skeleton, source);
  return mapping;
}

// The fingertip end site: a child node of the distal index joint that carries no mesh.
std::optional<Vec3> tip_end_site(const tinygltf::Model& model, const gltf::NodeTree& tree,
                                 const gltf::JointNodes& joints, int distal, const Mat3d& R,
                                 const PoseD& T_model_distal) {
  for (const int child : model.nodes[joints.node[distal]].children) {
    if (model.nodes[child].mesh < 0) {
      const Vec3d p_model = R * tree.global[child].topRightCorner<3, 1>();
      const PoseD T_distal_model = inverse(T_model_distal);
      return (T_distal_model.R * p_model + T_distal_model.t).cast<float>();
    }
  }
  return std::nullopt;
}

}  // namespace

Avatar load_avatar(std::span<const std::uint8_t> bytes, const std::string& source,
                   const std::filesystem::path& base_dir) {
  const tinygltf::Model model = parse(bytes, source, base_dir);
  const gltf::NodeTree tree = gltf::read_node_tree(model, source);
  const std::optional<gltf::VrmHumanoid> vrm = gltf::read_vrm_humanoid(model, source);
  const gltf::JointNodes joints =
      gltf::select_joint_nodes(tree, skeleton_nodes(model, source, vrm));
  const int n = static_cast<int>(joints.node.size());
  if (n > kMaxJoints) {
    throw Error(source + ": " + std::to_string(n) + " joints (at most " +
                std::to_string(kMaxJoints) + ")");
  }

  Avatar avatar;
  ik::Skeleton& skeleton = avatar.rig.skeleton;
  std::vector<PoseD> T_file_joint(n);
  for (int j = 0; j < n; ++j) {
    const int node = joints.node[j];
    const std::string& name = model.nodes[node].name;
    skeleton.joint_names.push_back(name.empty() ? "node" + std::to_string(node) : name);
    skeleton.parents.push_back(static_cast<std::int16_t>(joints.parent_joint[j]));
    T_file_joint[j] = rigid_part(tree.global[node], model, node, source);
  }
  skeleton.rest_local.assign(n, Pose{});  // the bone map checks only the hierarchy
  const BoneMapping mapping = map_bones(skeleton, joints, vrm, source);
  avatar.rig.joint = mapping.joint;
  avatar.bone_source = mapping.source;

  const double turn = facing_turn(T_file_joint[avatar.rig[ik::Bone::kLeftUpperArm]].t,
                                  T_file_joint[avatar.rig[ik::Bone::kRightUpperArm]].t, source);
  avatar.facing_turn = static_cast<float>(turn);
  const Mat3d R = yaw(turn);
  std::vector<PoseD> T_model_joint(n);
  for (int j = 0; j < n; ++j) {
    T_model_joint[j] = {R * T_file_joint[j].R, R * T_file_joint[j].t};
    const int parent = skeleton.parents[j];
    skeleton.rest_local[j] = to_float(
        parent == ik::kNoParent ? T_model_joint[j]
                                : compose(inverse(T_model_joint[parent]), T_model_joint[j]));
  }
  ik::validate(skeleton, source);

  gltf::check_mesh_budget(model, tree.depth_first, source);  // before baking allocates anything
  avatar.mesh = gltf::bake_rest_mesh(model, tree, joints, R, source);
  if (avatar.mesh.indices.empty()) {
    throw Error(source + ": the skinned mesh has no triangles");
  }
  std::vector<Pose> rest_model(n);
  ik::local_to_model(skeleton, skeleton.rest_local, rest_model);
  for (const Pose& T : rest_model) {
    avatar.mesh.inverse_bind.push_back(deixis::inverse(T));
  }

  std::array<std::optional<Vec3>, 2> tips;
  for (const auto& [hand, bone] : {std::pair{Hand::kLeft, ik::Bone::kLeftIndexDistal},
                                   std::pair{Hand::kRight, ik::Bone::kRightIndexDistal}}) {
    if (const int distal = avatar.rig[bone]; distal != -1) {
      tips[index(hand)] = tip_end_site(model, tree, joints, distal, R, T_model_joint[distal]);
    }
  }
  measure_rig(avatar.rig, avatar.mesh, tips);
  return avatar;
}

Avatar load_avatar(const std::filesystem::path& file) {
  const std::string source = file.string();
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec)) {
    throw Error(source + ": not a regular file");  // a pipe or device would never end
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw Error(source + ": cannot open");
  }
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) {
    throw Error(source + ": cannot read");
  }
  if (static_cast<std::uint64_t>(size) > kMaxFileBytes) {
    throw Error(source + ": " + std::to_string(size) + " bytes is more than the " +
                std::to_string(kMaxFileBytes >> 20) + " MiB an avatar may have");
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (!in) {
    throw Error(source + ": cannot read");
  }
  // External buffers are looked up beside the file ("." for a bare file name: an empty folder
  // would mean "no folder", data: URIs only).
  const std::filesystem::path folder = file.parent_path();
  return load_avatar(bytes, source, folder.empty() ? std::filesystem::path(".") : folder);
}

}  // namespace deixis::avatar
