#include "capture/tracker_noise.h"

#include <cmath>

#include "capture/random.h"
#include "core/error.h"

namespace deixis::capture {

namespace {

constexpr float kDegree = 0.017453292f;
// No drops in the first second: the runtime needs one valid frame to hold.
constexpr std::size_t kCleanStart = 30;

// A stationary AR(1) process per component: x ← ρx + √(1−ρ²)·σ·ε.
struct Correlated {
  Vec3 value = Vec3::Zero();
  Vec3 next(Random& rng, float sigma, float rho) {
    const float innovation = std::sqrt(1.0f - rho * rho) * sigma;
    for (int k = 0; k < 3; ++k) {
      value[k] = rho * value[k] + innovation * rng.normal();
    }
    return value;
  }
};

Mat3 small_rotation(const Vec3& rotation_vector) {
  const float angle = rotation_vector.norm();
  if (angle < 1e-9f) {
    return Mat3::Identity();
  }
  return Eigen::AngleAxisf(angle, rotation_vector / angle).toRotationMatrix();
}

Vec3 random_direction(Random& rng) {
  return Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
}

// Marks [start, start + length) of one part as dropped.
void drop(std::vector<std::uint8_t>& mask, std::size_t start, int length, std::uint8_t flag) {
  for (std::size_t i = start; i < mask.size() && i < start + static_cast<std::size_t>(length);
       ++i) {
    mask[i] |= flag;
  }
}

}  // namespace

TrackerNoise tracker_noise(std::string_view name) {
  TrackerNoise n;
  n.name = std::string(name);
  if (name == "none") {
    return n;
  }
  if (name == "mocap") {
    n.head_position = 0.0005f;
    n.head_rotation = 0.1f * kDegree;
    n.hand_position = 0.001f;
    n.hand_rotation = 0.3f * kDegree;
    n.tip_position = 0.001f;
    n.gaze = 0.3f * kDegree;
    n.correlation = 0.8f;
    return n;
  }
  if (name == "headset") {
    // Inside-out head tracking (≈1 mm, 0.2°), optical hand tracking (≈3 mm, 1.5°), eye tracking
    // (≈1° accuracy); hands glitch under occlusion and drop out; eyes blink ≈15 times a minute.
    n.head_position = 0.001f;
    n.head_rotation = 0.2f * kDegree;
    n.hand_position = 0.003f;
    n.hand_rotation = 1.5f * kDegree;
    n.tip_position = 0.003f;
    n.gaze = 1.0f * kDegree;
    n.correlation = 0.85f;
    n.spike_rate = 0.15f;
    n.spike_position = 0.045f;
    n.spike_rotation = 10.0f * kDegree;
    n.spike_frames = 3;
    n.hand_drop_rate = 0.08f;
    n.hand_drop_frames = 8;
    n.head_drop_rate = 0.01f;
    n.blink_rate = 0.25f;
    return n;
  }
  throw Error("unknown tracker noise '" + std::string(name) + "' (known: none, mocap, headset)");
}

void apply_tracker_noise(Sequence& s, const TrackerNoise& noise, std::uint64_t seed) {
  if (noise.name == "none") {
    return;
  }
  Random rng(seed);
  const float rho = noise.correlation;
  const double per_frame = 1.0 / kFrameRate;
  Correlated head_p, head_r, gaze;
  std::array<Correlated, 2> hand_p, hand_r, tip;

  // Which parts drop out when (decided first, so the noise draws do not depend on it).
  std::vector<std::uint8_t> dropped(s.size(), 0);
  for (std::size_t i = kCleanStart; i < s.size(); ++i) {
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      if (rng.chance(static_cast<double>(noise.hand_drop_rate) * per_frame)) {
        drop(dropped, i, rng.integer(1, noise.hand_drop_frames), tracked::hand(h));
      }
    }
    if (rng.chance(static_cast<double>(noise.head_drop_rate) * per_frame)) {
      drop(dropped, i, rng.integer(1, 3), tracked::kHead | tracked::kGaze);
    }
    if (rng.chance(static_cast<double>(noise.blink_rate) * per_frame)) {
      drop(dropped, i, rng.integer(3, 5), tracked::kGaze);  // a blink: 100–170 ms
    }
  }

  std::array<int, 2> spike_left = {0, 0};
  std::array<Vec3, 2> spike_offset{};
  std::array<Vec3, 2> spike_turn{};
  TrackingFrame held = s.frames.front();
  for (std::size_t i = 0; i < s.size(); ++i) {
    TrackingFrame& f = s.frames[i];
    // Continuous noise.
    f.T_world_head.translation += head_p.next(rng, noise.head_position, rho);
    f.T_world_head.rotation =
        small_rotation(head_r.next(rng, noise.head_rotation, rho)) * f.T_world_head.rotation;
    f.gaze = (small_rotation(gaze.next(rng, noise.gaze, rho)) * f.gaze).normalized();
    for (int h = 0; h < 2; ++h) {
      Pose& w = f.T_world_wrist[h];
      const Vec3 tip_in_wrist = transform_point(inverse(w), f.index_tip[h]);
      w.translation += hand_p[h].next(rng, noise.hand_position, rho);
      w.rotation = small_rotation(hand_r[h].next(rng, noise.hand_rotation, rho)) * w.rotation;
      // Occlusion spikes move the whole hand estimate for a few frames.
      if (spike_left[h] == 0 && rng.chance(static_cast<double>(noise.spike_rate) * per_frame)) {
        spike_left[h] = rng.integer(1, noise.spike_frames);
        spike_offset[h] = noise.spike_position * rng.uniform(0.5f, 1.0f) * random_direction(rng);
        spike_turn[h] = noise.spike_rotation * rng.uniform(0.5f, 1.0f) * random_direction(rng);
      }
      if (spike_left[h] > 0) {
        w.translation += spike_offset[h];
        w.rotation = small_rotation(spike_turn[h]) * w.rotation;
        --spike_left[h];
      }
      f.index_tip[h] = transform_point(w, tip_in_wrist) + tip[h].next(rng, noise.tip_position, rho);
    }
    // Dropped parts hold their last valid values.
    f.valid = static_cast<std::uint8_t>(tracked::kAll & ~dropped[i]);
    if (!(f.valid & tracked::kHead)) {
      f.T_world_head = held.T_world_head;
    }
    if (!(f.valid & tracked::kGaze)) {
      f.gaze = held.gaze;
    }
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      if (!(f.valid & tracked::hand(h))) {
        f.T_world_wrist[index(h)] = held.T_world_wrist[index(h)];
        f.index_tip[index(h)] = held.index_tip[index(h)];
      }
    }
    held = f;
  }
}

}  // namespace deixis::capture
