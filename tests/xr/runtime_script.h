#pragma once
// A tracked person as the OpenXR test runtime's script (xr_test_runtime/script.h, docs/xr.md):
// head, eye gaze, wrist joints and index fingertips key by key, so that a synthetic capture's
// person can wear the scripted headset.

#include <nlohmann/json.hpp>

#include <span>
#include <string>

#include "core/tracking.h"
#include "xr/input.h"

namespace deixis::xr {

inline nlohmann::json vec(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

// A Deixis wrist frame as the OpenXR wrist joint it is read from (the inverse of
// wrist_from_joint).
inline nlohmann::json joint_of(const Pose& T_world_wrist, Hand hand) {
  const Mat3 R_joint_wrist = wrist_from_joint(Pose{}, hand).rotation;
  const Quat q(Mat3(T_world_wrist.rotation * R_joint_wrist.transpose()));
  return {{"position", vec(T_world_wrist.translation)},
          {"orientation", {q.x(), q.y(), q.z(), q.w()}}};
}

// The runtime's script for tracking frames at 30 Hz: one key per frame, the session ending after
// the last. `realtime`: paced to the wall clock (for sessions with other processes).
inline std::string runtime_script(std::span<const TrackingFrame> frames, bool realtime) {
  nlohmann::json keys = nlohmann::json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const TrackingFrame& f = frames[i];
    const Quat head(Mat3(f.T_world_head.rotation));
    nlohmann::json key = {{"t", static_cast<double>(i) / 30.0},
                          {"head",
                           {{"position", vec(f.T_world_head.translation)},
                            {"orientation", {head.x(), head.y(), head.z(), head.w()}}}},
                          {"gaze", vec(f.gaze)}};
    for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
      const auto h = static_cast<std::size_t>(index(hand));
      key[hand == Hand::kLeft ? "left" : "right"] =
          (f.valid & tracked::hand(hand)) == 0
              ? nlohmann::json(nullptr)
              : nlohmann::json{{"wrist", joint_of(f.T_world_wrist[h], hand)},
                               {"index_tip", vec(f.index_tip[h])}};
    }
    keys.push_back(key);
  }
  return nlohmann::json{
      {"display_hz", 30}, {"realtime", realtime}, {"frames", frames.size()}, {"keys", keys}}
      .dump();
}

}  // namespace deixis::xr
