#include "avatar/rig_measurements.h"

#include <algorithm>
#include <limits>
#include <vector>

#include "core/tracking.h"

namespace deixis::avatar {

namespace {

using ik::Bone;

constexpr float kEyeBelowTop = 1.0f - 0.936f;  // fraction of stature (Winter)
constexpr float kEyeBehindFace = 0.02f;        // fraction of stature
constexpr float kHandLength = 0.108f;          // fraction of stature (Winter)

struct Side {
  Bone upper_arm, lower_arm, hand, proximal, intermediate, distal;
};
constexpr std::array<Side, 2> kSides = {  // by deixis::Hand
    Side{Bone::kLeftUpperArm, Bone::kLeftLowerArm, Bone::kLeftHand, Bone::kLeftIndexProximal,
         Bone::kLeftIndexIntermediate, Bone::kLeftIndexDistal},
    Side{Bone::kRightUpperArm, Bone::kRightLowerArm, Bone::kRightHand, Bone::kRightIndexProximal,
         Bone::kRightIndexIntermediate, Bone::kRightIndexDistal}};

// The joint each vertex follows most.
int dominant_joint(const SkinnedMesh& mesh, std::size_t v) {
  return mesh.joints[v][0];  // weights are stored in decreasing order
}

bool is_at_or_below(const ik::Skeleton& s, int joint, int ancestor) {
  for (int j = joint; j != ik::kNoParent; j = s.parents[j]) {
    if (j == ancestor) {
      return true;
    }
  }
  return false;
}

Vec3 eye_midpoint(const ik::HumanoidRig& rig, const std::vector<Pose>& model,
                  const SkinnedMesh& mesh) {
  const int left = rig[Bone::kLeftEye];
  const int right = rig[Bone::kRightEye];
  if (left != -1 && right != -1) {
    return 0.5f * (model[left].translation + model[right].translation);
  }
  const int head = rig[Bone::kHead];
  float top = -std::numeric_limits<float>::infinity();
  float front = std::numeric_limits<float>::infinity();
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (is_at_or_below(rig.skeleton, dominant_joint(mesh, v), head)) {
      top = std::max(top, mesh.positions[v].y());
      front = std::min(front, mesh.positions[v].z());  // the face is towards −Z
    }
  }
  const Vec3 p = model[head].translation;
  if (!std::isfinite(top)) {  // nothing skinned to the head: a typical offset from the head joint
    return p + Vec3(0.0f, 0.06f * rig.height, -0.05f * rig.height);
  }
  return Vec3(p.x(), top - kEyeBelowTop * rig.height, front + kEyeBehindFace * rig.height);
}

Vec3 fingertip_in_distal(const ik::HumanoidRig& rig, const std::vector<Pose>& model,
                         const SkinnedMesh& mesh, int distal) {
  const int previous = rig.skeleton.parents[distal];
  const Vec3 p = model[distal].translation;
  const Vec3 bone = p - model[previous].translation;
  const Vec3 along = bone.normalized();
  float reach = 0.0f;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (dominant_joint(mesh, v) == distal) {
      reach = std::max(reach, (mesh.positions[v] - p).dot(along));
    }
  }
  if (reach <= 0.0f) {
    reach = 0.8f * bone.norm();
  }
  return transform_point(inverse(model[distal]), p + reach * along);
}

float arm_length(const ik::HumanoidRig& rig, const std::vector<Pose>& model, const Side& side,
                 const Vec3& tip_in_distal) {
  float length = 0.0f;
  int previous = rig[side.upper_arm];
  for (const Bone b : {side.lower_arm, side.hand, side.proximal, side.intermediate, side.distal}) {
    if (const int j = rig[b]; j != -1) {
      length += (model[j].translation - model[previous].translation).norm();
      previous = j;
    }
  }
  if (rig[side.distal] != -1) {
    return length + tip_in_distal.norm();
  }
  return length + kHandLength * rig.height;
}

}  // namespace

void measure_rig(ik::HumanoidRig& rig, const SkinnedMesh& mesh,
                 const std::array<std::optional<Vec3>, 2>& tip_end_sites) {
  std::vector<Pose> model(rig.skeleton.rest_local.size());
  ik::local_to_model(rig.skeleton, rig.skeleton.rest_local, model);

  float bottom = std::numeric_limits<float>::infinity();
  float top = -std::numeric_limits<float>::infinity();
  for (const Vec3& p : mesh.positions) {
    bottom = std::min(bottom, p.y());
    top = std::max(top, p.y());
  }
  rig.height = mesh.positions.empty() ? 0.0f : top - bottom;

  rig.eye_midpoint_in_head =
      transform_point(inverse(model[rig[Bone::kHead]]), eye_midpoint(rig, model, mesh));

  float total = 0.0f;
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    const Side& side = kSides[index(hand)];
    Vec3& tip = rig.index_tip_in_distal[index(hand)];
    tip = Vec3::Zero();
    if (const int distal = rig[side.distal]; distal != -1) {
      tip = tip_end_sites[index(hand)].value_or(fingertip_in_distal(rig, model, mesh, distal));
    }
    total += arm_length(rig, model, side, tip);
  }
  rig.arm_length = 0.5f * total;
}

}  // namespace deixis::avatar
