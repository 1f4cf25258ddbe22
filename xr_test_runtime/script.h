#pragma once
// The scripted user the test runtime tracks (DEIXIS_XR_SCRIPT, a JSON file; docs/xr.md): head,
// eye gaze and both hands over time, key by key, linearly interpolated (orientations slerped).
// Poses are OpenXR's: hand wrists as XR_HAND_JOINT_WRIST_EXT (−Z distal, +Y dorsal), in the
// STAGE space (floor at y = 0), times in seconds from the first frame's predicted display time.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace deixis::xrt {

struct ScriptPose {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
};

struct ScriptHand {
  bool tracked = false;
  ScriptPose wrist;
  Eigen::Vector3f index_tip = Eigen::Vector3f::Zero();
};

struct ScriptSample {
  ScriptPose head;                                   // the eye midpoint
  Eigen::Vector3f gaze = Eigen::Vector3f(0, 0, -1);  // unit, stage frame
  std::array<ScriptHand, 2> hands;                   // 0 left, 1 right
};

struct ScriptKey {
  double t = 0.0;
  ScriptSample sample;
};

struct Script {
  double display_hz = 90.0;
  float ipd = 0.063f;           // m between the two views
  long frames = 0;              // after this many ended frames the runtime asks to exit; 0: never
  long lose_after_frames = 0;   // then LOSS_PENDING instead of STOPPING (tests); 0: never
  bool realtime = false;        // xrWaitFrame sleeps until the frame's wall-clock time, as a
                                // headset's compositor paces frames (for runs that talk to
                                // real-time processes); false: frames as fast as the app goes
  std::vector<ScriptKey> keys;  // ascending t, at least one

  ScriptSample at(double t) const;
};

// A standing user looking ahead with hands at rest (no file given).
Script default_script();

// Reads and validates a script; on failure returns nothing and sets `error` (file, field, why).
std::optional<Script> load_script(const std::string& path, std::string& error);

}  // namespace deixis::xrt
