#include "gesture/translation_loop.h"

#include <algorithm>
#include <cstring>

namespace deixis {

namespace {

constexpr int kUserColumns = nn::kMpnetFeatures;
constexpr int kAvatarColumns = nn::kUgnetColumns;
constexpr int kTargetAt = nn::kPoseSize;                            // in an avatar row
constexpr int kProgressionAt = nn::kPoseSize + kTargetFeatureSize;  // in an avatar row

// Drops the oldest row of a row-major window and returns the (now stale) newest row to fill.
template <std::size_t N>
float* shift_window(std::array<float, N>& window, int columns) {
  std::memmove(window.data(), window.data() + columns, (N - columns) * sizeof(float));
  return window.data() + N - columns;
}

float lerp(float a, float b, float t) {
  return (1.0f - t) * a + t * b;
}

// Blends one 3-vector of x, optionally renormalising it (unit-vector parts).
void blend_vec3(const EndEffectors& predicted, const EndEffectors& user, int at, float weight,
                float predicted_scale, bool unit, EndEffectors& out) {
  Vec3 v;
  for (int k = 0; k < 3; ++k) {
    v[k] = lerp(predicted_scale * predicted[at + k], user[at + k], weight);
  }
  if (unit) {
    const float n = v.norm();
    if (n > 1e-12f) {
      v /= n;
    }
  }
  set_vec3(out, at, v);
}

}  // namespace

void BlendCounters::update(const nn::Progression& p) {
  const float gaze = p[0], deictic = p[1], idle = p[2];
  head = std::clamp(head + ((idle < kIdleBelow && gaze < kGazeBelow) ? 1 : -1), 0, kMax);
  hand = std::clamp(hand + ((idle < kIdleBelow && deictic < kDeicticBelow) ? 1 : -1), 0, kMax);
}

EndEffectors blend_end_effectors(const EndEffectors& predicted, const EndEffectors& user,
                                 float head_weight, float hand_weight, float scale) {
  EndEffectors out{};
  // Head side (weight b^H): gaze, head rotation (unit), head position.
  blend_vec3(predicted, user, ee::kGaze, head_weight, 1.0f, true, out);
  blend_vec3(predicted, user, ee::kHeadForward, head_weight, 1.0f, true, out);
  blend_vec3(predicted, user, ee::kHeadUp, head_weight, 1.0f, true, out);
  blend_vec3(predicted, user, ee::kHeadPosition, head_weight, 1.0f, false, out);
  // Hand side (weight b^R): hand rotation (unit); hand position and fingertip scaled by
  // k = lerp(1/scale, 1, b^R), the size adaptation of paper Fig. 7.
  const float k = lerp(1.0f / scale, 1.0f, hand_weight);
  blend_vec3(predicted, user, ee::kHandForward, hand_weight, 1.0f, true, out);
  blend_vec3(predicted, user, ee::kHandUp, hand_weight, 1.0f, true, out);
  blend_vec3(predicted, user, ee::kHandPosition, hand_weight, k, false, out);
  blend_vec3(predicted, user, ee::kFingertip, hand_weight, k, false, out);
  return out;
}

TranslationLoop::TranslationLoop(nn::Mpnet mpnet, nn::Ugnet ugnet, float scale)
    : mpnet_(std::move(mpnet)), ugnet_(std::move(ugnet)), scale_(scale) {}

void TranslationLoop::reset(const TranslationInput& first, const EndEffectors& avatar_initial,
                            std::span<const float> noise) {
  for (int r = 0; r < kRows; ++r) {
    std::copy(first.user_features.begin(), first.user_features.end(),
              mpnet_window_.begin() + r * kUserColumns);
    float* row = ugnet_window_.data() + r * kAvatarColumns;
    std::copy(avatar_initial.begin(), avatar_initial.end(), row);
    std::copy(first.avatar_target.begin(), first.avatar_target.end(), row + kTargetAt);
    std::copy(kIdle.begin(), kIdle.end(), row + kProgressionAt);
  }
  counters_ = BlendCounters{};
  run_networks(noise);
}

TranslationStep TranslationLoop::step(const TranslationInput& frame, std::span<const float> noise) {
  TranslationStep out = begin_step(frame);
  end_step(ugnet_.run(ugnet_window_, noise), out);
  return out;
}

TranslationStep TranslationLoop::begin_step(const TranslationInput& frame) {
  return begin_step_with(frame, nullptr);
}

TranslationStep TranslationLoop::begin_step(const TranslationInput& frame,
                                            const nn::Progression& known) {
  return begin_step_with(frame, &known);
}

TranslationStep TranslationLoop::begin_step_with(const TranslationInput& frame,
                                                 const nn::Progression* known) {
  TranslationStep out = open_step(frame);
  take_mpnet(known != nullptr ? *known : mpnet_.run(mpnet_window_).progression, out);
  return out;
}

TranslationStep TranslationLoop::open_step(const TranslationInput& frame) {
  TranslationStep out;
  out.head_weight = counters_.head_weight();
  out.hand_weight = counters_.hand_weight();
  out.avatar_x =
      blend_end_effectors(prediction_, frame.user_x, out.head_weight, out.hand_weight, scale_);
  push_user_row(frame);
  push_avatar_row(out.avatar_x, frame.avatar_target);
  return out;
}

void TranslationLoop::take_mpnet(const nn::Progression& progression, TranslationStep& step) {
  take_progression(progression);
  step.progression = progression_;
}

void TranslationLoop::end_step(const nn::PoseVector& prediction, TranslationStep& step) {
  prediction_ = prediction;
  step.prediction = prediction_;
}

void TranslationLoop::push_user_row(const TranslationInput& frame) {
  float* row = shift_window(mpnet_window_, kUserColumns);
  std::copy(frame.user_features.begin(), frame.user_features.end(), row);
}

void TranslationLoop::push_avatar_row(const EndEffectors& avatar_x, const TargetFeature& target) {
  float* row = shift_window(ugnet_window_, kAvatarColumns);
  std::copy(avatar_x.begin(), avatar_x.end(), row);
  std::copy(target.begin(), target.end(), row + kTargetAt);
  // The progression column of this row is MPNet's output on the window ending at this frame,
  // written by run_networks().
}

void TranslationLoop::run_networks(std::span<const float> noise) {
  run_mpnet();
  prediction_ = ugnet_.run(ugnet_window_, noise);
}

// MPNet on the user's window; its progression goes into the avatar's newest row (which UGNet
// reads next) and drives the blend counters of the next step.
void TranslationLoop::run_mpnet() {
  take_progression(mpnet_.run(mpnet_window_).progression);
}

void TranslationLoop::take_progression(const nn::Progression& progression) {
  progression_ = progression;
  std::copy(progression_.begin(), progression_.end(),
            ugnet_window_.end() - kAvatarColumns + kProgressionAt);
  counters_.update(progression_);
}

}  // namespace deixis
