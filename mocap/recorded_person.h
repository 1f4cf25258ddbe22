#pragma once
// A recording performed as a site's user (docs/bvh.md#driving-a-site): the recorded person
// stands on the site's floor spot and faces where the spot faces (the recording's ground at its
// first frame, SkeletonTracking::ground, moved onto the spot by one yaw and translation), played
// through BvhPlayer's interpolation at the site's rate, looping or once (then held at the last
// frame, so the tracking stays valid), with the body calibration from the first upright frame
// or as the site's file states it, placed the same way.

#include <optional>
#include <vector>

#include "core/tracking.h"
#include "mocap/player.h"

namespace deixis::mocap {

// A body the site's file states instead of measuring it: the person is taken as standing upright
// on the spot (eyes at 0.936 of the height, as gesture/upright_calibration.cpp).
struct StatedBody {
  float height = 1.70f;      // m
  float arm_length = 0.74f;  // m, shoulder to fingertip
};

// How a site plays a recording.
struct RecordingPlay {
  double metres_per_unit = 1.0;  // the file's unit, resolved (never "auto" here)
  Playback playback = Playback::kLoop;
  Hand deictic_hand = Hand::kRight;
  std::optional<StatedBody> body;  // none: calibrated from the first upright frame
};

struct RecordedPerson {
  BodyCalibration body;               // in the room, as the site's hello sends it
  std::vector<TrackingFrame> frames;  // in the room; frames[i].time = i / rate
};

// T_world_recording: the yaw and translation that put frame 0's ground onto `T_world_floor`.
Pose recording_placement(SkeletonTracking& tracking, const Pose& T_world_floor);
// Every pose, point and direction of `frame` moved by `T_world_recording`.
void place(const Pose& T_world_recording, TrackingFrame& frame);
// A stated body standing upright on the spot.
BodyCalibration stated_calibration(const StatedBody& body, Hand deictic_hand,
                                   const Pose& T_world_floor);

// The recording at `rate` Hz for `seconds` (0: once through, first to last frame), placed on
// `T_world_floor`. Throws deixis::Error (naming the file) without an upright frame to calibrate
// from when no body is stated.
RecordedPerson perform_recording(const Bvh& bvh, const RecordingPlay& play,
                                 const Pose& T_world_floor, double seconds, double rate = 30.0);

}  // namespace deixis::mocap
