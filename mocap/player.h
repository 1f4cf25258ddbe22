#pragma once
// A recording played as a person (groundwork for a site's virtual_user driven by a BVH file,
// docs/bvh.md#playing): the tracking at any time t, looping or once, interpolated between the
// two recorded frames around t (positions linearly, rotations by slerp, so Euler angles never
// wrap). Allocates nothing per call.

#include <cstddef>

#include "mocap/skeleton_tracking.h"

namespace deixis::mocap {

enum class Playback : unsigned char { kOnce, kLoop };

class BvhPlayer {
 public:
  // `bvh` must outlive the player.
  BvhPlayer(const Bvh& bvh, double metres_per_unit, Playback playback);

  // The tracking at `time` s from the recording's start (out.time = time). Once: held at the
  // first frame before 0 and at the last after the end. Loop: the recording repeats, its last
  // frame followed by its first.
  void at(double time, TrackingFrame& out);

  double duration() const;  // s, first to last frame
  SkeletonTracking& tracking() { return tracking_; }

 private:
  const Bvh& bvh_;
  Playback playback_;
  SkeletonTracking tracking_;
  TrackingFrame a_;
  TrackingFrame b_;
};

// How many samples at `rate` Hz cover `span` s, both ends included. Frame times are often written
// rounded (CMU's .0083333 for 1/120 s: 360 frames last 2.99999 s): a sample within 1 % of an
// interval past the end still counts.
std::size_t sample_count(double span, double rate);

}  // namespace deixis::mocap
