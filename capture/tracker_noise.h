#pragma once
// What a tracker does to motion (paper §V.D): continuous noise (temporally correlated, AR(1)),
// occasional jitter spikes (occlusion: a hand jumps for a frame or a few), and dropped frames
// (the part is flagged invalid; blinks drop the gaze). A dropped part holds its last valid
// values, so a frame is always complete; its flag tells the reader not to trust it.

#include <cstdint>
#include <string>
#include <string_view>

#include "capture/sequence.h"

namespace deixis::capture {

struct TrackerNoise {
  std::string name = "none";
  // Continuous noise: standard deviations (m, rad) and the frame-to-frame correlation.
  float head_position = 0, head_rotation = 0;
  float hand_position = 0, hand_rotation = 0, tip_position = 0;
  float gaze = 0;
  float correlation = 0;
  // Jitter spikes of a hand: rate (1/s per hand), size (m, rad), up to this many frames.
  float spike_rate = 0, spike_position = 0, spike_rotation = 0;
  int spike_frames = 1;
  // Dropped parts: rates (1/s) and the longest drop (frames).
  float hand_drop_rate = 0, head_drop_rate = 0, blink_rate = 0;
  int hand_drop_frames = 1;
};

// "none", "mocap" (marker capture: sub-millimetre, no drops) or "headset" (an XR headset's head,
// eye and hand tracking: millimetres and degrees, spikes, drops and blinks). An unknown name is a
// deixis::Error listing these.
TrackerNoise tracker_noise(std::string_view name);

// Applies the noise in place; the same seed gives the same noise.
void apply_tracker_noise(Sequence& sequence, const TrackerNoise& noise, std::uint64_t seed);

}  // namespace deixis::capture
