#pragma once
// The smooth 0 → 1 ramp the presence layer's fades share (touch contact, gaze and pointing
// settling): 0 at or below 0, 1 at or above 1, 3t² − 2t³ between, flat at both ends so a weight
// that crosses them never jumps in slope.
#include <algorithm>

namespace deixis {

inline float smoothstep(float x) {
  const float t = std::clamp(x, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace deixis
