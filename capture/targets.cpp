#include "capture/targets.h"

#include <cmath>

#include "capture/actor.h"
#include "core/error.h"

namespace deixis::capture {

namespace {

constexpr float kDegree = 0.017453292f;
constexpr int kAttempts = 200;

// A direction in the stance frame from azimuth (positive to the left) and elevation.
Vec3 direction(float azimuth, float elevation) {
  return {-std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
          -std::cos(azimuth) * std::cos(elevation)};
}

}  // namespace

TargetRules low_target_rules() {
  return TargetRules{-50.0f, -25.0f};
}

TargetSampler::TargetSampler(const Motion& motion, Random& rng, const TargetRules& rules)
    : motion_(motion), rng_(rng), rules_(rules) {}

Vec3 TargetSampler::in_world(const Vec3& p) const {
  return transform_point(motion_.stance(), p);
}

Vec3 TargetSampler::eyes() const {
  return in_world(Vec3(0, motion_.body().eye_height(), 0));
}

bool TargetSampler::apart(const Vec3& p, const std::vector<TargetObject>& others) const {
  const Vec3 e = eyes();
  for (const TargetObject& o : others) {
    const float cos_angle = (p - e).normalized().dot((o.position - e).normalized());
    if (cos_angle > std::cos(kMinSeparation)) {
      return false;
    }
  }
  return true;
}

TargetObject TargetSampler::pointing(TargetId id, const std::vector<TargetObject>& others) {
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    const float azimuth = rng_.uniform(-75.0f, 75.0f) * kDegree;
    const float elevation =
        rng_.uniform(rules_.pointing_elevation_min_deg, rules_.pointing_elevation_max_deg) *
        kDegree;
    // Mostly beyond arm's reach (log-uniform 0.9–5 m), sometimes near (0.3–0.9 m).
    const float distance = rng_.chance(0.1)
                               ? rng_.uniform(0.3f, 0.9f)
                               : std::exp(rng_.uniform(std::log(0.9f), std::log(5.0f)));
    const Vec3 p = eyes() + motion_.stance().rotation * (distance * direction(azimuth, elevation));
    if (!apart(p, others)) {
      continue;
    }
    const float size = std::clamp(0.03f + 0.05f * distance, 0.05f, 0.35f);
    const TargetKind kind = rng_.chance(0.3) ? TargetKind::kBox : TargetKind::kSphere;
    return TargetObject{id, "object " + std::to_string(id), kind, p, Vec3::Constant(size)};
  }
  throw Error("capture: no pointing target found apart from the others");
}

TargetObject TargetSampler::touching(TargetId id, const std::vector<TargetObject>& others) {
  const Body& body = motion_.body();
  const float lateral = body.subject.handedness == Hand::kRight ? -1.0f : 1.0f;  // azimuth sign
  const float reach_scale = body.subject.arm_length / 0.74f;
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    // Mostly on the hand's own side, some across the body; from a little below the eyes to
    // about hip height; 0.3–0.55 m from the body's axis (scaled by arm length).
    const float azimuth = lateral * rng_.uniform(-50.0f, 75.0f) * kDegree;
    const float height = rng_.uniform(-0.75f, -0.05f);
    const float radius = rng_.uniform(0.30f, 0.55f) * reach_scale;
    const Vec3 p_stance(-std::sin(azimuth) * radius, body.eye_height() + height,
                        -std::cos(azimuth) * radius);
    const float size = rng_.uniform(0.02f, 0.06f);
    TargetObject target{id, "object " + std::to_string(id), TargetKind::kSphere, in_world(p_stance),
                        Vec3::Constant(size)};
    if (apart(target.position, others) && touch_torso(motion_, target)) {
      return target;
    }
  }
  throw Error("capture: no touch target within reach found apart from the others");
}

TargetObject TargetSampler::partner(const std::vector<TargetObject>& others) {
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    const float azimuth = rng_.uniform(-50.0f, 50.0f) * kDegree;
    const float distance = rng_.uniform(1.0f, 2.5f);
    const float eye_height = rng_.uniform(1.45f, 1.85f);
    const Vec3 p_stance = distance * direction(azimuth, 0.0f) + Vec3(0, eye_height, 0);
    const Vec3 p = in_world(p_stance);
    if (apart(p, others)) {
      return TargetObject{kPartnerTarget, "partner", TargetKind::kSphere, p, Vec3::Constant(0.2f)};
    }
  }
  throw Error("capture: no place for the partner found apart from the targets");
}

}  // namespace deixis::capture
