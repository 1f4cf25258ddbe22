#pragma once
// The scripted user the test runtime tracks (DEIXIS_XR_SCRIPT, a JSON file; docs/xr.md): head,
// eye gaze and both hands over time, key by key, linearly interpolated (orientations slerped).
// Poses are OpenXR's: hand wrists as XR_HAND_JOINT_WRIST_EXT (−Z distal, +Y dorsal), in the
// STAGE space (floor at y = 0), times in seconds from the first frame's predicted display time.
// Besides poses: the controllers' buttons, triggers and sticks (by input identifier, per
// top-level user path), which blend modes the headset offers, which interaction profiles its
// devices can be, and which frames' images the record keeps.

#include <openxr/openxr.h>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "xr_test_runtime/profiles.h"

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

// One input identifier's state ("trigger", "thumbstick", "select"): what each component of it
// reads. Buttons and touches hold from key to key; value, force and the axes are interpolated.
struct ScriptControl {
  bool click = false;
  bool touch = false;
  float value = 0.0f;  // [0, 1]
  float force = 0.0f;  // [0, 1]
  float x = 0.0f;      // [-1, 1]
  float y = 0.0f;      // [-1, 1]
};

struct ScriptInput {
  TopLevel top = TopLevel::kRight;
  std::string identifier;  // as the profiles name it: "select", "trigger", "thumbstick", ...
  ScriptControl control;
};

struct ScriptKey {
  double t = 0.0;
  ScriptSample sample;
  std::vector<ScriptInput> inputs;  // the controls held or moved at this key; others at rest
};

struct Script {
  double display_hz = 90.0;
  float ipd = 0.063f;          // m between the two views
  long frames = 0;             // after this many ended frames the runtime asks to exit; 0: never
  long lose_after_frames = 0;  // then LOSS_PENDING instead of STOPPING (tests); 0: never
  bool realtime = false;       // xrWaitFrame sleeps until the frame's wall-clock time, as a
                               // headset's compositor paces frames (for runs that talk to
                               // real-time processes); false: frames as fast as the app goes
  // What the headset offers, in order (xrEnumerateEnvironmentBlendModes; xrEndFrame refuses
  // others).
  std::vector<XrEnvironmentBlendMode> blend_modes = {XR_ENVIRONMENT_BLEND_MODE_OPAQUE};
  // The interaction profiles the headset's devices can be, in preference order: each top-level
  // user path takes the first one the application suggested bindings for. Default: all, in
  // profiles() order (khr/simple_controller first).
  std::vector<std::string> profiles;
  // Frames (indices from 0) whose projection views the record keeps as images with their alpha.
  std::vector<long> capture_frames;
  std::vector<ScriptKey> keys;  // ascending t, at least one

  ScriptSample at(double t) const;
  // The state of `identifier` on `top` at time t (all at rest when no key holds it).
  ScriptControl control_at(double t, TopLevel top, std::string_view identifier) const;
};

// A standing user looking ahead with hands at rest (no file given).
Script default_script();

// Reads and validates a script; on failure returns nothing and sets `error` (file, field, why).
std::optional<Script> load_script(const std::string& path, std::string& error);

}  // namespace deixis::xrt
