#pragma once
// What the application did, for tests to check: every frame it submitted (with the display time
// the runtime predicted for it), every call the runtime refused and why, the session states it
// went through. Written as JSON to DEIXIS_XR_RECORD when the instance is destroyed.

#include <openxr/openxr.h>

#include <cstdint>
#include <string>
#include <vector>

namespace deixis::xrt {

struct RecordedFrame {
  std::uint64_t index = 0;  // 0, 1, 2, ... in the order frames were begun
  XrTime predicted_display_time = 0;
  XrTime submitted_display_time = 0;
  std::uint32_t layers = 0;
  std::uint32_t projection_views = 0;
  std::uint32_t synced_actions = 0;  // xrSyncActions calls since the previous frame ended
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

  // Writes the record to `path`; false when it cannot.
  bool write(const std::string& path) const;
};

}  // namespace deixis::xrt
