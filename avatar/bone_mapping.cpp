#include "avatar/bone_mapping.h"

#include <utility>

#include "core/error.h"

namespace deixis::avatar {

namespace {

using ik::Bone;

// (ancestor, descendant) pairs a humanoid's hierarchy must respect where both bones are present.
constexpr std::array<std::pair<Bone, Bone>, 26> kBelow = {{
    {Bone::kHips, Bone::kSpine},
    {Bone::kSpine, Bone::kChest},
    {Bone::kSpine, Bone::kHead},
    {Bone::kChest, Bone::kNeck},
    {Bone::kNeck, Bone::kHead},
    {Bone::kHead, Bone::kLeftEye},
    {Bone::kHead, Bone::kRightEye},
    {Bone::kSpine, Bone::kLeftUpperArm},
    {Bone::kLeftShoulder, Bone::kLeftUpperArm},
    {Bone::kLeftUpperArm, Bone::kLeftLowerArm},
    {Bone::kLeftLowerArm, Bone::kLeftHand},
    {Bone::kLeftHand, Bone::kLeftIndexProximal},
    {Bone::kLeftIndexProximal, Bone::kLeftIndexIntermediate},
    {Bone::kLeftIndexIntermediate, Bone::kLeftIndexDistal},
    {Bone::kLeftHand, Bone::kLeftIndexDistal},
    {Bone::kSpine, Bone::kRightUpperArm},
    {Bone::kRightShoulder, Bone::kRightUpperArm},
    {Bone::kRightUpperArm, Bone::kRightLowerArm},
    {Bone::kRightLowerArm, Bone::kRightHand},
    {Bone::kRightHand, Bone::kRightIndexProximal},
    {Bone::kRightIndexProximal, Bone::kRightIndexIntermediate},
    {Bone::kRightIndexIntermediate, Bone::kRightIndexDistal},
    {Bone::kRightHand, Bone::kRightIndexDistal},
    {Bone::kChest, Bone::kLeftShoulder},
    {Bone::kChest, Bone::kRightShoulder},
    {Bone::kHips, Bone::kHead},
}};

bool is_below(const ik::Skeleton& skeleton, int joint, int ancestor) {
  for (int j = skeleton.parents[joint]; j != ik::kNoParent; j = skeleton.parents[j]) {
    if (j == ancestor) {
      return true;
    }
  }
  return false;
}

// Built by appending: GCC 12 at -O3 misreports `"'" + std::string + "'"` (-Wrestrict, bug 105329).
std::string quoted(std::string_view text) {
  std::string s;
  s.reserve(text.size() + 2);
  s += '\'';
  s += text;
  s += '\'';
  return s;
}

std::string joint_label(const ik::Skeleton& skeleton, int joint) {
  return quoted(skeleton.joint_names[joint]);
}

struct Candidate {
  BoneMapping mapping;
  int required = 0;
  int found = 0;
  std::string duplicate;  // the first bone two joints claim, described
};

Candidate map_with(NamingScheme scheme, const ik::Skeleton& skeleton) {
  Candidate c;
  c.mapping.scheme = scheme;
  c.mapping.source = "joint names (" + std::string(scheme_name(scheme)) + ")";
  for (int j = 0; j < skeleton.joint_count(); ++j) {
    const std::optional<Bone> bone = bone_for_name(scheme, skeleton.joint_names[j]);
    if (!bone) {
      continue;
    }
    int& slot = c.mapping.joint[static_cast<int>(*bone)];
    if (slot != -1) {
      if (c.duplicate.empty()) {
        c.duplicate = "joints " + std::to_string(slot) + " " + joint_label(skeleton, slot) +
                      " and " + std::to_string(j) + " " + joint_label(skeleton, j) +
                      " both name bone " + quoted(ik::bone_name(*bone)) + " (" +
                      std::string(scheme_name(scheme)) + " names)";
      }
      continue;
    }
    slot = j;
    ++c.found;
    if (ik::is_required(*bone)) {
      ++c.required;
    }
  }
  return c;
}

}  // namespace

BoneMapping map_bones_by_name(const ik::Skeleton& skeleton, const std::string& file) {
  Candidate best = map_with(NamingScheme::kDeixis, skeleton);
  for (const NamingScheme scheme : {NamingScheme::kMixamo, NamingScheme::kBcn}) {
    Candidate c = map_with(scheme, skeleton);
    if (c.required > best.required || (c.required == best.required && c.found > best.found)) {
      best = std::move(c);
    }
  }
  if (!best.duplicate.empty()) {
    throw Error(file + ": " + best.duplicate);
  }
  return best.mapping;
}

void check_bone_mapping(const BoneMapping& mapping, const ik::Skeleton& skeleton,
                        const std::string& file) {
  std::string missing;
  int missing_count = 0;
  for (int b = 0; b < ik::kBoneCount; ++b) {
    const Bone bone = static_cast<Bone>(b);
    if (mapping.joint[b] != -1 || !ik::is_required(bone)) {
      continue;
    }
    missing += missing.empty() ? "" : ", ";
    missing += quoted(ik::bone_name(bone));
    if (mapping.scheme) {
      missing += " (a joint named " + quoted(expected_name(*mapping.scheme, bone)) + ")";
    }
    ++missing_count;
  }
  if (missing_count > 0) {
    throw Error(file + ": missing required bone" + (missing_count > 1 ? "s " : " ") + missing +
                "; bones looked up by " + mapping.source);
  }
  for (const auto& [above, below] : kBelow) {
    const int a = mapping.joint[static_cast<int>(above)];
    const int d = mapping.joint[static_cast<int>(below)];
    if (a != -1 && d != -1 && !is_below(skeleton, d, a)) {
      throw Error(file + ": bone " + quoted(ik::bone_name(below)) + " (joint " +
                  joint_label(skeleton, d) + ") is not below bone " + quoted(ik::bone_name(above)) +
                  " (joint " + joint_label(skeleton, a) + ")");
    }
  }
}

}  // namespace deixis::avatar
