#pragma once
// Which environment blend mode `deixis xr` submits in (docs/xr.md, "Mixed reality"): a passthrough
// or see-through headset shows the real room behind the layer (ALPHA_BLEND: the layer's alpha
// decides; ADDITIVE: black shows nothing), so Deixis prefers those and then draws only the
// remote people's avatars on a transparent background; an opaque headset gets the virtual room.

#include <openxr/openxr.h>

#include <array>
#include <optional>
#include <span>
#include <string_view>

namespace deixis::xr {

enum class BlendChoice { kAuto, kOpaque, kAlpha, kAdditive };

// The --blend values, in BlendChoice's order.
inline constexpr std::array<std::string_view, 4> kBlendChoiceNames = {"auto", "opaque", "alpha",
                                                                      "additive"};

// One of kBlendChoiceNames; nullopt for anything else.
std::optional<BlendChoice> parse_blend_choice(std::string_view text);

// "opaque", "alpha", "additive" (the --blend spelling of a mode).
const char* blend_mode_name(XrEnvironmentBlendMode mode);

// The mode to submit in among those the system offers (any order): auto prefers ALPHA_BLEND,
// then ADDITIVE, then OPAQUE; any other choice must be offered. Throws deixis::Error naming the
// choice and what the system offers when it cannot be had (or nothing known is offered).
XrEnvironmentBlendMode choose_blend_mode(std::span<const XrEnvironmentBlendMode> offered,
                                         BlendChoice choice);

// True where the real room shows behind the layer: nothing of the virtual room is drawn.
bool see_through(XrEnvironmentBlendMode mode);

// The projection layer's flags: in ALPHA_BLEND the texture's alpha is what blends it with the
// world (premultiplied: the background is cleared to 0 and the avatars are opaque).
XrCompositionLayerFlags projection_layer_flags(XrEnvironmentBlendMode mode);

}  // namespace deixis::xr
