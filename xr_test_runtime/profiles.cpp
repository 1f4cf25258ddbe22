#include "xr_test_runtime/profiles.h"

#include <array>
#include <cctype>

namespace deixis::xrt {

namespace {

constexpr std::uint8_t kL = 1 << 0;  // /user/hand/left
constexpr std::uint8_t kR = 1 << 1;  // /user/hand/right
constexpr std::uint8_t kHands = kL | kR;
constexpr std::uint8_t kH = 1 << 2;  // /user/head
constexpr std::uint8_t kG = 1 << 3;  // /user/gamepad
constexpr std::uint8_t kE = 1 << 4;  // /user/eyes_ext

constexpr std::uint16_t kXY = kX | kY;

// The tables below are the spec's §6.4 lists (OpenXR 1.0), one row per input identifier.
constexpr ProfileIdentifier kSimpleIds[] = {
    {"select", kClick, kHands}, {"menu", kClick, kHands},    {"grip", kPose, kHands},
    {"aim", kPose, kHands},     {"haptic", kHaptic, kHands},
};
constexpr ProfileIdentifier kDaydreamIds[] = {
    {"select", kClick, kHands},
    {"trackpad", kXY | kClick | kTouch, kHands},
    {"grip", kPose, kHands},
    {"aim", kPose, kHands},
};
constexpr ProfileIdentifier kViveIds[] = {
    {"system", kClick, kHands},
    {"squeeze", kClick, kHands},
    {"menu", kClick, kHands},
    {"trigger", kClick | kValue, kHands},
    {"trackpad", kXY | kClick | kTouch, kHands},
    {"grip", kPose, kHands},
    {"aim", kPose, kHands},
    {"haptic", kHaptic, kHands},
};
constexpr ProfileIdentifier kViveProIds[] = {
    {"system", kClick, kH},
    {"volume_up", kClick, kH},
    {"volume_down", kClick, kH},
    {"mute_mic", kClick, kH},
};
constexpr ProfileIdentifier kMotionIds[] = {
    {"menu", kClick, kHands},
    {"squeeze", kClick, kHands},
    {"trigger", kValue, kHands},
    {"thumbstick", kXY | kClick, kHands},
    {"trackpad", kXY | kClick | kTouch, kHands},
    {"grip", kPose, kHands},
    {"aim", kPose, kHands},
    {"haptic", kHaptic, kHands},
};
constexpr ProfileIdentifier kXboxIds[] = {
    {"menu", kClick, kG},
    {"view", kClick, kG},
    {"a", kClick, kG},
    {"b", kClick, kG},
    {"x", kClick, kG},
    {"y", kClick, kG},
    {"dpad_down", kClick, kG},
    {"dpad_right", kClick, kG},
    {"dpad_up", kClick, kG},
    {"dpad_left", kClick, kG},
    {"shoulder_left", kClick, kG},
    {"shoulder_right", kClick, kG},
    {"thumbstick_left", kXY | kClick, kG},
    {"thumbstick_right", kXY | kClick, kG},
    {"trigger_left", kValue, kG},
    {"trigger_right", kValue, kG},
    {"haptic_left", kHaptic, kG},
    {"haptic_right", kHaptic, kG},
    {"haptic_left_trigger", kHaptic, kG},
    {"haptic_right_trigger", kHaptic, kG},
};
constexpr ProfileIdentifier kGoIds[] = {
    {"system", kClick, kHands}, {"trigger", kClick, kHands},
    {"back", kClick, kHands},   {"trackpad", kXY | kClick | kTouch, kHands},
    {"grip", kPose, kHands},    {"aim", kPose, kHands},
};
constexpr ProfileIdentifier kTouchIds[] = {
    {"x", kClick | kTouch, kL},
    {"y", kClick | kTouch, kL},
    {"menu", kClick, kL},
    {"a", kClick | kTouch, kR},
    {"b", kClick | kTouch, kR},
    {"system", kClick, kR},
    {"squeeze", kValue, kHands},
    {"trigger", kValue | kTouch, kHands},
    {"thumbstick", kXY | kClick | kTouch, kHands},
    {"thumbrest", kTouch, kHands},
    {"grip", kPose, kHands},
    {"aim", kPose, kHands},
    {"haptic", kHaptic, kHands},
};
constexpr ProfileIdentifier kIndexIds[] = {
    {"system", kClick | kTouch, kHands},
    {"a", kClick | kTouch, kHands},
    {"b", kClick | kTouch, kHands},
    {"squeeze", kValue | kForce, kHands},
    {"trigger", kClick | kValue | kTouch, kHands},
    {"thumbstick", kXY | kClick | kTouch, kHands},
    {"trackpad", kXY | kForce | kTouch, kHands},
    {"grip", kPose, kHands},
    {"aim", kPose, kHands},
    {"haptic", kHaptic, kHands},
};
constexpr ProfileIdentifier kEyeGazeIds[] = {
    {"gaze_ext", kPose, kE},
};

constexpr Profile kProfiles[] = {
    {"/interaction_profiles/khr/simple_controller", "Simple Controller", nullptr, kHands,
     kSimpleIds},
    {"/interaction_profiles/google/daydream_controller", "Daydream Controller", nullptr, kHands,
     kDaydreamIds},
    {"/interaction_profiles/htc/vive_controller", "Vive Controller", nullptr, kHands, kViveIds},
    {"/interaction_profiles/htc/vive_pro", "Vive Pro", nullptr, kH, kViveProIds},
    {"/interaction_profiles/microsoft/motion_controller", "Mixed Reality Motion Controller",
     nullptr, kHands, kMotionIds},
    {"/interaction_profiles/microsoft/xbox_controller", "Xbox Controller", nullptr, kG, kXboxIds},
    {"/interaction_profiles/oculus/go_controller", "Go Controller", nullptr, kHands, kGoIds},
    {"/interaction_profiles/oculus/touch_controller", "Touch Controller", nullptr, kHands,
     kTouchIds},
    {"/interaction_profiles/valve/index_controller", "Index Controller", nullptr, kHands,
     kIndexIds},
    {"/interaction_profiles/ext/eye_gaze_interaction", "Eye Gaze Interaction",
     "XR_EXT_eye_gaze_interaction", kE, kEyeGazeIds},
};

constexpr std::array<std::string_view, kTopLevelCount> kTopPaths = {
    "/user/hand/left", "/user/hand/right", "/user/head", "/user/gamepad", "/user/eyes_ext"};
constexpr std::array<std::string_view, kTopLevelCount> kTopNames = {"Left Hand", "Right Hand",
                                                                    "Head", "Gamepad", "Eyes"};
constexpr std::array<std::string_view, kTopLevelCount> kTopKeys = {"left", "right", "head",
                                                                   "gamepad", "eyes"};

struct ComponentName {
  Component bit;
  std::string_view name;
};
constexpr ComponentName kComponentNames[] = {
    {kClick, "click"}, {kTouch, "touch"}, {kValue, "value"}, {kForce, "force"},
    {kX, "x"},         {kY, "y"},         {kPose, "pose"}};

bool starts_with(std::string_view s, std::string_view prefix, std::string_view& rest) {
  if (s.substr(0, prefix.size()) != prefix) {
    return false;
  }
  rest = s.substr(prefix.size());
  return true;
}

}  // namespace

std::string_view top_level_path(TopLevel top) {
  return kTopPaths[static_cast<std::size_t>(top)];
}
std::string_view top_level_name(TopLevel top) {
  return kTopNames[static_cast<std::size_t>(top)];
}
std::string_view top_level_key(TopLevel top) {
  return kTopKeys[static_cast<std::size_t>(top)];
}

std::span<const Profile> profiles() {
  return kProfiles;
}

const Profile* find_profile(std::string_view path) {
  for (const Profile& p : kProfiles) {
    if (p.path == path) {
      return &p;
    }
  }
  return nullptr;
}

std::optional<BindingPath> parse_binding(const Profile& profile, std::string_view path) {
  for (std::size_t t = 0; t < kTopLevelCount; ++t) {
    std::string_view rest;
    if ((profile.top_levels & (1u << t)) == 0 || !starts_with(path, kTopPaths[t], rest)) {
      continue;
    }
    BindingPath out;
    out.top = static_cast<TopLevel>(t);
    const bool output = starts_with(rest, "/output/", rest);
    if (!output && !starts_with(rest, "/input/", rest)) {
      return std::nullopt;
    }
    const std::size_t slash = rest.find('/');
    const std::string_view identifier = rest.substr(0, slash);
    const std::string_view component =
        slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
    for (const ProfileIdentifier& id : profile.identifiers) {
      if (id.identifier != identifier || (id.top_levels & (1u << t)) == 0) {
        continue;
      }
      out.identifier = &id;
      if (output) {
        // Outputs are the identifier alone.
        return (id.components & kHaptic) != 0 && slash == std::string_view::npos
                   ? std::optional(out)
                   : std::nullopt;
      }
      if ((id.components & kHaptic) != 0) {
        return std::nullopt;  // an output named as an input
      }
      if (slash == std::string_view::npos) {
        return out;  // the identifier alone: the runtime picks the component
      }
      for (const ComponentName& c : kComponentNames) {
        if (c.name == component && (id.components & c.bit) != 0) {
          out.component = c.bit;
          return out;
        }
      }
      return std::nullopt;
    }
    return std::nullopt;
  }
  return std::nullopt;
}

std::uint16_t bound_component(XrActionType type, const BindingPath& binding) {
  const std::uint16_t has = binding.identifier->components;
  const std::uint16_t c = binding.component;
  // The component an identifier alone stands for, by the action's type (first that exists).
  const auto pick = [has](std::initializer_list<std::uint16_t> order) -> std::uint16_t {
    for (const std::uint16_t bit : order) {
      if ((has & bit) != 0) {
        return bit;
      }
    }
    return 0;
  };
  switch (type) {
    case XR_ACTION_TYPE_BOOLEAN_INPUT:
      if (c == 0) {
        return pick({kClick, kValue, kForce, kTouch});
      }
      return (c & (kClick | kTouch | kValue | kForce)) != 0 ? c : 0;
    case XR_ACTION_TYPE_FLOAT_INPUT:
      if (c == 0) {
        return pick({kValue, kForce, kClick, kTouch});
      }
      return (c & (kClick | kTouch | kValue | kForce | kX | kY)) != 0 ? c : 0;
    case XR_ACTION_TYPE_VECTOR2F_INPUT:
      return c == 0 && (has & kXY) == kXY ? kXY : 0;
    case XR_ACTION_TYPE_POSE_INPUT:
      return (has & kPose) != 0 && (c == 0 || c == kPose) ? kPose : 0;
    case XR_ACTION_TYPE_VIBRATION_OUTPUT:
      return (has & kHaptic) != 0 ? kHaptic : 0;
    default:
      return 0;
  }
}

bool known_identifier(std::string_view identifier) {
  for (const Profile& p : kProfiles) {
    for (const ProfileIdentifier& id : p.identifiers) {
      if (id.identifier == identifier && (id.components & (kHaptic | kPose)) == 0) {
        return true;
      }
    }
  }
  return false;
}

std::string localized_component(const BindingPath& binding) {
  // "thumbstick_left" + "x" -> "Thumbstick Left X".
  std::string words(binding.identifier->identifier);
  for (const ComponentName& c : kComponentNames) {
    if (c.bit == binding.component) {
      words += "_";
      words += c.name;
    }
  }
  bool start = true;
  for (char& ch : words) {
    if (ch == '_') {
      ch = ' ';
      start = true;
    } else if (start) {
      ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      start = false;
    }
  }
  return words;
}

}  // namespace deixis::xrt
