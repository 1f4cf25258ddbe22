#pragma once
// The interaction profiles the test runtime accepts: every profile of the OpenXR 1.0 core
// specification (§6.4, "Interaction Profile Paths") and of the extensions it offers
// (XR_EXT_eye_gaze_interaction), with the input and output paths each profile defines for each
// top-level user path. xrSuggestInteractionProfileBindings accepts exactly these paths (the
// spec's allowlist; anything else is XR_ERROR_PATH_UNSUPPORTED), attaching binds them by type,
// and the script drives their inputs by identifier (docs/xr.md, "Script").

#include <openxr/openxr.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace deixis::xrt {

// The top-level user paths the profiles use.
enum class TopLevel : std::uint8_t { kLeft, kRight, kHead, kGamepad, kEyes };
inline constexpr std::size_t kTopLevelCount = 5;

std::string_view top_level_path(TopLevel top);  // "/user/hand/left", ...
std::string_view top_level_name(TopLevel top);  // "Left Hand", ...
// The script's key for a top-level path ("left", "right", "head", "gamepad"; "eyes").
std::string_view top_level_key(TopLevel top);

// The components of an input identifier (§6.3, "input subpaths"), as bits.
enum Component : std::uint16_t {
  kClick = 1 << 0,
  kTouch = 1 << 1,
  kValue = 1 << 2,
  kForce = 1 << 3,
  kX = 1 << 4,
  kY = 1 << 5,
  kPose = 1 << 6,
  kHaptic = 1 << 7,  // an output (/output/<identifier>), not an input
};

// One identifier of a profile: "trigger" with value and touch, on both hands.
struct ProfileIdentifier {
  std::string_view identifier;
  std::uint16_t components;  // Component bits
  std::uint8_t top_levels;   // bit per TopLevel that has it
};

struct Profile {
  std::string_view path;    // "/interaction_profiles/khr/simple_controller"
  std::string_view name;    // localized: "Simple Controller"
  const char* extension;    // the extension that defines it, or nullptr for the core spec
  std::uint8_t top_levels;  // bit per TopLevel it applies to
  std::span<const ProfileIdentifier> identifiers;
};

std::span<const Profile> profiles();
const Profile* find_profile(std::string_view path);

// A binding path of a profile, taken apart: /user/hand/left/input/trigger/value is (left,
// "trigger", kValue); an identifier without component (/input/trigger) has component 0 and the
// runtime picks one by the action's type; /output/haptic is ("haptic", kHaptic).
struct BindingPath {
  TopLevel top = TopLevel::kLeft;
  const ProfileIdentifier* identifier = nullptr;
  std::uint16_t component = 0;
};

// The binding path in `profile`'s allowlist, or nothing when the profile does not define it.
std::optional<BindingPath> parse_binding(const Profile& profile, std::string_view path);

// The component an action of `type` reads from `binding`, or 0 when the types do not fit (a
// pose action on a button, an input action on a haptic output, a vector2 action on one axis).
// Booleans read click, touch or a thresholded value; floats a value, force, axis or button;
// vector2 actions an identifier with x and y; poses a pose; vibrations a haptic output.
std::uint16_t bound_component(XrActionType type, const BindingPath& binding);

// Whether `identifier` names an input of any profile (for validating scripts).
bool known_identifier(std::string_view identifier);

// "Trigger Value", "Thumbstick Left X", "Haptic": the component's localized name.
std::string localized_component(const BindingPath& binding);

}  // namespace deixis::xrt
