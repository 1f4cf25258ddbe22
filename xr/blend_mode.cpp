#include "xr/blend_mode.h"

#include <algorithm>
#include <array>
#include <string>

#include "core/error.h"

namespace deixis::xr {
namespace {

bool offers(std::span<const XrEnvironmentBlendMode> offered, XrEnvironmentBlendMode mode) {
  return std::find(offered.begin(), offered.end(), mode) != offered.end();
}

std::string offered_names(std::span<const XrEnvironmentBlendMode> offered) {
  std::string names;
  for (const XrEnvironmentBlendMode mode : offered) {
    names += (names.empty() ? "" : ", ") + std::string(blend_mode_name(mode));
  }
  return names.empty() ? "nothing" : names;
}

}  // namespace

std::optional<BlendChoice> parse_blend_choice(std::string_view text) {
  for (std::size_t i = 0; i < kBlendChoiceNames.size(); ++i) {
    if (text == kBlendChoiceNames[i]) {
      return static_cast<BlendChoice>(i);
    }
  }
  return std::nullopt;
}

const char* blend_mode_name(XrEnvironmentBlendMode mode) {
  switch (mode) {
    case XR_ENVIRONMENT_BLEND_MODE_OPAQUE:
      return "opaque";
    case XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND:
      return "alpha";
    case XR_ENVIRONMENT_BLEND_MODE_ADDITIVE:
      return "additive";
    default:
      return "unknown";
  }
}

XrEnvironmentBlendMode choose_blend_mode(std::span<const XrEnvironmentBlendMode> offered,
                                         BlendChoice choice) {
  constexpr std::array kPreference = {XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND,
                                      XR_ENVIRONMENT_BLEND_MODE_ADDITIVE,
                                      XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
  if (choice == BlendChoice::kAuto) {
    for (const XrEnvironmentBlendMode mode : kPreference) {
      if (offers(offered, mode)) {
        return mode;
      }
    }
    throw Error("--blend auto: the OpenXR system offers no known environment blend mode (" +
                offered_names(offered) + ")");
  }
  const XrEnvironmentBlendMode wanted =
      choice == BlendChoice::kOpaque  ? XR_ENVIRONMENT_BLEND_MODE_OPAQUE
      : choice == BlendChoice::kAlpha ? XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND
                                      : XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
  if (!offers(offered, wanted)) {
    throw Error(std::string("--blend ") + blend_mode_name(wanted) +
                ": the OpenXR system offers only " + offered_names(offered));
  }
  return wanted;
}

bool see_through(XrEnvironmentBlendMode mode) {
  return mode == XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND ||
         mode == XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
}

XrCompositionLayerFlags projection_layer_flags(XrEnvironmentBlendMode mode) {
  return mode == XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND
             ? XrCompositionLayerFlags{XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT}
             : XrCompositionLayerFlags{0};
}

}  // namespace deixis::xr
