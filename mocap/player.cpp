#include "mocap/player.h"

#include <algorithm>
#include <cmath>

namespace deixis::mocap {

namespace {

Mat3 slerp(const Mat3& a, const Mat3& b, float w) {
  return Quat(a).slerp(w, Quat(b)).normalized().toRotationMatrix();
}

Pose blend(const Pose& a, const Pose& b, float w) {
  return {slerp(a.rotation, b.rotation, w), a.translation + w * (b.translation - a.translation)};
}

}  // namespace

BvhPlayer::BvhPlayer(const Bvh& bvh, double metres_per_unit, Playback playback)
    : bvh_(bvh), playback_(playback), tracking_(bvh, metres_per_unit) {}

double BvhPlayer::duration() const {
  return static_cast<double>(bvh_.frames() - 1) * bvh_.frame_time;
}

void BvhPlayer::at(double time, TrackingFrame& out) {
  const std::size_t n = bvh_.frames();
  double position = time / bvh_.frame_time;  // in frames
  if (playback_ == Playback::kLoop) {
    position = std::fmod(position, static_cast<double>(n));
    if (position < 0) {
      position += static_cast<double>(n);
    }
  } else {
    position = std::clamp(position, 0.0, static_cast<double>(n - 1));
  }
  const auto i = std::min(static_cast<std::size_t>(position), n - 1);
  const std::size_t j = i + 1 < n ? i + 1 : (playback_ == Playback::kLoop ? 0 : i);
  const auto w = static_cast<float>(position - static_cast<double>(i));
  tracking_.track(i, a_);
  tracking_.track(j, b_);
  out = a_;
  out.time = time;
  out.valid = a_.valid & b_.valid;
  out.T_world_head = blend(a_.T_world_head, b_.T_world_head, w);
  out.gaze = (a_.gaze + w * (b_.gaze - a_.gaze)).normalized();
  for (std::size_t h = 0; h < 2; ++h) {
    out.T_world_wrist[h] = blend(a_.T_world_wrist[h], b_.T_world_wrist[h], w);
    out.index_tip[h] = a_.index_tip[h] + w * (b_.index_tip[h] - a_.index_tip[h]);
  }
}

std::size_t sample_count(double span, double rate) {
  return static_cast<std::size_t>(std::floor(span * rate + 0.01)) + 1;
}

}  // namespace deixis::mocap
