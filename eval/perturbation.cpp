#include "eval/perturbation.h"

#include <numbers>

#include "gesture/features.h"

namespace deixis::eval {

namespace {

constexpr int kDropEvery = 30;            // frames between the authors' drop points (1 s)
constexpr double kDropProbability = 0.3;  // per drop point (paper: 30 % per second)
constexpr double kJitterProbability = 0.03;
constexpr float kDegree = std::numbers::pi_v<float> / 180.0f;

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  Vec3 v(n(rng), n(rng), n(rng));
  while (v.norm() < 1e-6f) {
    v = Vec3(n(rng), n(rng), n(rng));
  }
  return v.normalized();
}

Mat3 rotation_vector(const Vec3& v) {
  const float angle = v.norm();
  return angle > 0.0f ? Mat3(Eigen::AngleAxisf(angle, v / angle)) : Mat3::Identity();
}

// Moves a pose rigidly by a rotation about its own origin and a translation; `carried` points
// (the fingertip) move with it.
void displace(Pose& T, const Mat3& R, const Vec3& dp, Vec3* carried) {
  if (carried) {
    *carried = R * (*carried - T.translation) + T.translation + dp;
  }
  T.rotation = R * T.rotation;
  T.translation += dp;
}

void jitter(TrackingFrame& f, Hand hand, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  if (u(rng) >= static_cast<float>(kJitterProbability)) {
    return;
  }
  const Vec3 dp = random_unit(rng) * (0.05f + 0.10f * u(rng));
  const Mat3 R = rotation_vector(random_unit(rng) * (10.0f + 20.0f * u(rng)) * kDegree);
  if (u(rng) < 0.5f) {
    displace(f.T_world_head, R, dp, nullptr);
  } else {
    const auto h = static_cast<std::size_t>(index(hand));
    displace(f.T_world_wrist[h], R, dp, &f.index_tip[h]);
  }
}

void continuous_noise(TrackingFrame& f, Hand hand, std::mt19937_64& rng) {
  std::normal_distribution<float> position(0.0f, 0.01f);
  std::normal_distribution<float> angle(0.0f, 2.0f * kDegree);
  const auto sample_rotation = [&] {
    return rotation_vector(Vec3(angle(rng), angle(rng), angle(rng)));
  };
  const auto sample_position = [&] { return Vec3(position(rng), position(rng), position(rng)); };
  displace(f.T_world_head, sample_rotation(), sample_position(), nullptr);
  const auto h = static_cast<std::size_t>(index(hand));
  displace(f.T_world_wrist[h], sample_rotation(), sample_position(), &f.index_tip[h]);
  std::normal_distribution<float> gaze(0.0f, 1.0f * kDegree);
  f.gaze = (rotation_vector(Vec3(gaze(rng), gaze(rng), gaze(rng))) * f.gaze).normalized();
}

}  // namespace

std::size_t apply_missed_tracking(std::vector<TranslationInput>& frames, int drop_frames,
                                  std::mt19937_64& rng) {
  std::bernoulli_distribution drop(kDropProbability);
  std::size_t held = 0;
  const auto n = frames.size();
  for (std::size_t start = 0; start < n; start += kDropEvery) {
    if (!drop(rng)) {
      continue;
    }
    // The row before the drop (the 30-row prefix repeats frame 0, so frame 0 holds itself).
    const TranslationInput last = frames[start == 0 ? 0 : start - 1];
    for (std::size_t k = start; k < std::min(n, start + static_cast<std::size_t>(drop_frames));
         ++k) {
      frames[k].user_features = last.user_features;
      frames[k].user_x = last.user_x;
      ++held;
    }
  }
  return held;
}

void recompute_user_rows(const TestSet& set, std::size_t s, std::size_t first, Perturbation kind,
                         std::mt19937_64& rng, std::vector<TranslationInput>& frames) {
  const BodyCalibration& body = set.body(s);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    TrackingFrame f = set.tracking(s, first + k);
    if (kind == Perturbation::kJitter) {
      jitter(f, body.deictic_hand, rng);
    } else if (kind == Perturbation::kContinuousNoise) {
      continuous_noise(f, body.deictic_hand, rng);
    }
    frames[k].user_features = mpnet_features(f, body);
    frames[k].user_x = end_effectors(f, body);
  }
}

}  // namespace deixis::eval
