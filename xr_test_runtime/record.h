#pragma once
// What the application did, for tests to check: every frame it submitted (with the display time
// the runtime predicted for it), every call the runtime refused and why, the session states it
// went through. Written as JSON to DEIXIS_XR_RECORD when the instance is destroyed.

#include <openxr/openxr.h>

#include <cstdint>
#include <string>
#include <vector>

namespace deixis::xrt {

// A captured projection view (script "capture_frames"): the image file, and how many of its
// pixels are transparent (alpha 0), opaque (alpha 255) or in between.
struct RecordedImage {
  std::string file;  // PAM (RGBA), next to the record
  std::uint32_t width = 0, height = 0;
  std::uint64_t transparent = 0, opaque = 0, partial = 0;
};

struct RecordedLayer {
  std::string type;                // "projection" or "quad"
  std::vector<std::string> flags;  // XrCompositionLayerFlags, e.g. "BLEND_TEXTURE_SOURCE_ALPHA"
  std::uint32_t views = 0;
  std::vector<RecordedImage> images;  // captured frames only
};

struct RecordedFrame {
  std::uint64_t index = 0;  // 0, 1, 2, ... in the order frames were begun
  XrTime predicted_display_time = 0;
  XrTime submitted_display_time = 0;
  std::uint32_t layers = 0;
  std::uint32_t projection_views = 0;
  std::uint32_t synced_actions = 0;  // xrSyncActions calls since the previous frame ended
  std::string blend_mode;            // "OPAQUE", "ADDITIVE" or "ALPHA_BLEND"
  std::vector<RecordedLayer> layer_list;
};

// xrApplyHapticFeedback (or xrStopHapticFeedback, with `stop`) as the application asked it.
struct RecordedHaptic {
  XrTime time = 0;  // the input time (the last frame's predicted display time)
  std::string action;
  std::string subaction;  // empty for all
  bool stop = false;
  XrDuration duration = 0;
  float frequency = 0.0f;
  float amplitude = 0.0f;
  std::vector<std::string> outputs;  // the bound outputs it reached
};

// A suggested binding attaching left unbound because the action's type does not fit the input
// (spec §11.4: a runtime is free to ignore any suggested binding).
struct RecordedIgnoredBinding {
  std::string action;
  std::string path;
};

struct RecordedRefusal {
  std::string call;
  std::string result;
};

struct Record {
  std::vector<RecordedFrame> frames;
  std::vector<RecordedRefusal> refusals;
  std::vector<std::string> states;
  std::uint32_t syncs_since_frame = 0;
  std::string interaction = "none";  // "hand_tracking", "controllers", or "none"
  bool gaze_bound = false;
  std::string graphics = "none";  // "egl", "xlib" or "headless" once a session is made
  std::vector<std::pair<std::string, std::string>> profiles;  // (top-level path, profile)
  std::vector<RecordedIgnoredBinding> ignored_bindings;
  std::vector<RecordedHaptic> haptics;
  std::uint64_t haptics_dropped = 0;  // beyond kMaxHaptics
  static constexpr std::size_t kMaxHaptics = 10000;

  // Writes the record to `path`; false when it cannot.
  bool write(const std::string& path) const;
};

}  // namespace deixis::xrt
