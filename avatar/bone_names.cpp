#include "avatar/bone_names.h"

#include <array>

namespace deixis::avatar {

namespace {

using Names = std::array<std::string_view, ik::kBoneCount>;

// In ik::Bone order: hips, spine, chest, neck, head, eyes, then per side shoulder, upper arm,
// lower arm, hand and the three index joints.
constexpr Names kMixamo = {"Hips",           "Spine",          "Spine1",          "Neck",
                           "Head",           "LeftEye",        "RightEye",        "LeftShoulder",
                           "LeftArm",        "LeftForeArm",    "LeftHand",        "LeftHandIndex1",
                           "LeftHandIndex2", "LeftHandIndex3", "RightShoulder",   "RightArm",
                           "RightForeArm",   "RightHand",      "RightHandIndex1", "RightHandIndex2",
                           "RightHandIndex3"};

// BCN_Epileptic has four spine joints (B_Spine1..4) and a neck made of B_Root_Neck_T/H and
// B_Neck, which carries the eyes, jaw and lips: it is the head. Its one finger chain, B_Finger1..3,
// stands for the index.
constexpr Names kBcn = {"B_Root_Pelvis_L", "B_Spine1",       "B_Spine3",         "B_Root_Neck_T",
                        "B_Neck",          "B_Eye_Left",     "B_Eye_Right",      "B_Clavicle_Left",
                        "B_UpperArm_Left", "B_ForeArm_Left", "B_Hand_Left",      "B_Finger1_Left",
                        "B_Finger2_Left",  "B_Finger3_Left", "B_Clavicle_Right", "B_UpperArm_Right",
                        "B_ForeArm_Right", "B_Hand_Right",   "B_Finger1_Right",  "B_Finger2_Right",
                        "B_Finger3_Right"};

// Mixamo's exporters write "mixamorig:Hips"; other tools turn the colon into an underscore and
// number repeated imports ("mixamorig1_Hips"). Anything before the last colon is a namespace.
std::string_view strip_mixamo_namespace(std::string_view name) {
  if (const auto colon = name.rfind(':'); colon != std::string_view::npos) {
    return name.substr(colon + 1);
  }
  constexpr std::string_view kPrefix = "mixamorig";
  if (name.starts_with(kPrefix)) {
    std::size_t i = kPrefix.size();
    while (i < name.size() && name[i] >= '0' && name[i] <= '9') {
      ++i;
    }
    if (i < name.size() && name[i] == '_') {
      return name.substr(i + 1);
    }
  }
  return name;
}

std::string_view name_in(NamingScheme scheme, int bone) {
  switch (scheme) {
    case NamingScheme::kDeixis:
      return ik::bone_name(static_cast<ik::Bone>(bone));
    case NamingScheme::kMixamo:
      return kMixamo[bone];
    case NamingScheme::kBcn:
      return kBcn[bone];
  }
  return {};
}

}  // namespace

std::string_view scheme_name(NamingScheme scheme) {
  switch (scheme) {
    case NamingScheme::kDeixis:
      return "Deixis/VRM";
    case NamingScheme::kMixamo:
      return "Mixamo";
    case NamingScheme::kBcn:
      return "BCN";
  }
  return "?";
}

std::optional<ik::Bone> bone_for_name(NamingScheme scheme, std::string_view joint_name) {
  const std::string_view name =
      scheme == NamingScheme::kMixamo ? strip_mixamo_namespace(joint_name) : joint_name;
  for (int b = 0; b < ik::kBoneCount; ++b) {
    if (name_in(scheme, b) == name) {
      return static_cast<ik::Bone>(b);
    }
  }
  return std::nullopt;
}

std::string_view expected_name(NamingScheme scheme, ik::Bone bone) {
  const int b = static_cast<int>(bone);
  return b >= 0 && b < ik::kBoneCount ? name_in(scheme, b) : std::string_view{};
}

}  // namespace deixis::avatar
