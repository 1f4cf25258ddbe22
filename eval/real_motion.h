#pragma once
// The translator measured on a recording of real motion (docs/eval.md#real-motion-bvh): the
// recording sampled at the networks' 30 Hz, its person calibrated, their targets selected in the
// room of real_motion_room.h as a headset user's are (gesture/target_selection.h), and the
// translator of each weight set run over it toward the avatar's room, where every copy stands
// elsewhere. Per recording and weight set:
//  (a) following: on the frames where the person designates nothing (no target within the
//      selection's 12° of the gaze ray, nor of the eye → fingertip ray with the arm extended, none
//      touched; the selection itself keeps the last target looked at), the translator's head H and
//      deictic wrist (gesture/translator.h, before IK) against the same parts of the pose copied
//      onto the avatar's root (presence/pose_copy.h): position (cm) and rotation (°) errors, their
//      mean, per second of motion and in the worst second;
//  (b) belief: the time share with MPNet's progression above 0.5 per channel, and onsets per
//      minute (a frame above 0.5 after one at or below);
//  (c) agreement: the mean |p − p_reference| per channel against the reference set's MPNet (the
//      authors') on the same frames: MPNet reads only the person's rows, so both translators'
//      MPNets read the same windows.

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "mocap/bvh.h"

namespace deixis::eval {

inline constexpr double kRealMotionRateHz = 30.0;  // the networks' and the wire's rate

// A recording as a site would send it: its tracking at 30 Hz and its body calibration.
struct Recording {
  std::string name;  // the file's name
  std::vector<TrackingFrame> frames;
  BodyCalibration body;
  std::string unit;           // the length unit used (inferred, docs/bvh.md#units)
  double source_rate_hz = 0;  // the file's own frame rate
  std::size_t source_frames = 0;

  double seconds() const { return static_cast<double>(frames.size()) / kRealMotionRateHz; }
};

// The recording through mocap's player (positions linear, rotations slerped) at 30 Hz from its
// first frame to its last, the deictic hand the right one (recordings do not say which).
Recording sample_recording(const mocap::Bvh& bvh, double metres_per_unit, std::string name);
// read_bvh, the unit inferred; every error is a deixis::Error that names the file.
Recording load_recording(const std::filesystem::path& file);

// The networks a site runs (MPNet GRU-MoE and UGNet MoE, AC) of one weight set's right hand.
struct MotionNetworks {
  std::string label;
  nn::Mpnet mpnet;
  nn::Ugnet ugnet;
};
MotionNetworks load_motion_networks(const std::string& label, const std::filesystem::path& dir);

// Channels of nn::Progression: gaze, deictic, idle.
using ChannelValues = std::array<double, 3>;

struct FollowingError {
  double head_cm = 0;
  double head_deg = 0;
  double hand_cm = 0;  // the deictic wrist
  double hand_deg = 0;
};

struct RealMotionFigures {
  std::string weights;
  FollowingError mean;                                    // over free frames
  FollowingError worst_second;                            // the largest per-second mean, per part
  std::vector<std::optional<FollowingError>> per_second;  // second s: its free frames' mean
  ChannelValues share_above_half{};                       // 0–1
  ChannelValues onsets_per_minute{};
  std::optional<ChannelValues> mpnet_difference;  // against the reference; none for itself
};

struct RealMotionResult {
  std::string recording;
  double seconds = 0;
  std::size_t frames = 0;
  std::size_t free_frames = 0;          // nothing designated by head or hand
  double head_designated = 0;           // share of frames with a head target
  double hand_designated = 0;           // share of frames with a hand target
  std::vector<RealMotionFigures> sets;  // in the order of `networks`
};

// Runs every set's translator over the recording. `reference`: the index of the set whose MPNet
// the others are compared with (c), or none.
RealMotionResult measure_real_motion(const Recording& recording,
                                     std::span<const MotionNetworks> networks,
                                     std::optional<std::size_t> reference);

}  // namespace deixis::eval
