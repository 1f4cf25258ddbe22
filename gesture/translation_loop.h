#pragma once
// The translation loop of the authors' harness (docs/conventions.md#translation-loop; paper §IV.C,
// eq. 6–9) on network vectors: per frame, MPNet reads the user's last 30 feature rows; its
// progression is shifted into the progression window (which starts as 30 rows of (0, 0, 1), idle);
// UGNet reads the avatar's last 30 rows (end-effectors, avatar target feature, progression) and
// predicts the avatar's end-effectors for the next frame; when that frame arrives, the prediction
// is blended with the user's end-effectors (eq. 8) by weights that rise while the user is not
// gesturing at a target and fall while they are (eq. 9), and the blend becomes the avatar's row for
// that frame.
//
// Everything is in the networks' frame, mirrored for a left-handed user (features.h does that);
// the loop itself is hand-agnostic. It reproduces the authors' rollout fixtures
// (tests/gesture/translation_loop_test.cpp). All state is fixed-size; step() never allocates.

#include <array>
#include <span>

#include "gesture/features.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"

namespace deixis {

// One frame of what the loop consumes: the user's MPNet features and end-effectors, and the
// avatar's target feature (its targets seen from its own root, in its own room).
struct TranslationInput {
  MpnetFeatureRow user_features{};
  EndEffectors user_x{};
  TargetFeature avatar_target{};
};

// Blend counters of eq. 9: c ∈ [0, 20], b = c/20 (δ = 0.05). The head counter rises while
// idle < 0.15 and gaze < 0.25, the hand counter while idle < 0.15 and deictic < 0.15; each falls
// otherwise (thresholds of the authors' test_UGNet.py, docs/conventions.md#blending).
struct BlendCounters {
  static constexpr int kMax = 20;
  static constexpr float kIdleBelow = 0.15f;
  static constexpr float kGazeBelow = 0.25f;
  static constexpr float kDeicticBelow = 0.15f;
  int head = 0;
  int hand = 0;

  void update(const nn::Progression& p);
  float head_weight() const { return static_cast<float>(head) / kMax; }
  float hand_weight() const { return static_cast<float>(hand) / kMax; }
};

// Eq. 8 as the authors' harness applies it: unit-vector parts are renormalised after blending;
// the hand position and fingertip of the prediction are scaled by k = lerp(1/scale, 1, b_hand)
// before blending, scale = user size / avatar size. `predicted` and the result are the avatar's.
EndEffectors blend_end_effectors(const EndEffectors& predicted, const EndEffectors& user,
                                 float head_weight, float hand_weight, float scale);

struct TranslationStep {
  EndEffectors avatar_x{};   // the avatar's end-effectors for this frame (network frame)
  float head_weight = 0.0f;  // the blend weights used for them
  float hand_weight = 0.0f;
  nn::Progression progression{};  // MPNet's output on the window ending at this frame
  EndEffectors prediction{};      // UGNet's prediction for the next frame
};

class TranslationLoop {
 public:
  static constexpr int kRows = nn::kWindowRows;
  static constexpr nn::Progression kIdle = {0.0f, 0.0f, 1.0f};

  // `scale` = user size / avatar size (ratio of heights).
  TranslationLoop(nn::Mpnet mpnet, nn::Ugnet ugnet, float scale);

  // Starts a new sequence: every window row becomes a copy of `first` (the user's and the
  // avatar's target rows) and of `avatar_initial` (the avatar's rows), the progression window
  // becomes idle, the blend counters zero; then the networks run once so that the first step()
  // has a prediction to blend. `noise` feeds a diffusion UGNet (nn/shapes.h); others ignore it.
  void reset(const TranslationInput& first, const EndEffectors& avatar_initial,
             std::span<const float> noise = {});

  // One frame: the avatar's row for this frame = blend(previous prediction, this frame's user
  // x); then MPNet and UGNet run on the windows ending at this frame. Allocation-free.
  TranslationStep step(const TranslationInput& frame, std::span<const float> noise = {});

  // step() in two halves, so that many loops' UGNets can run as one batch (deixis eval's
  // chains, nn::Ugnet::run_batch): begin_step() does all of a step but UGNet and returns it
  // without its prediction; the caller runs UGNet on ugnet_window() and hands the result to
  // end_step(), which completes the step. step() is exactly that with ugnet.run().
  TranslationStep begin_step(const TranslationInput& frame);
  void end_step(const nn::PoseVector& prediction, TranslationStep& step);
  // begin_step() when MPNet's output on the window ending at this frame is already known: MPNet
  // reads only the user's rows, so deixis eval, which chains one user's rows against many
  // avatars, computes them once per user. `known` must be what MPNet gives on that window.
  TranslationStep begin_step(const TranslationInput& frame, const nn::Progression& known);
  // begin_step() in two halves, so that MPNet too runs for many loops as one batch
  // (gesture/translator_batch.h): open_step() blends and shifts the windows; the caller runs MPNet
  // on mpnet_window() and hands its progression to take_mpnet(). begin_step() is exactly that.
  TranslationStep open_step(const TranslationInput& frame);
  void take_mpnet(const nn::Progression& progression, TranslationStep& step);

  const nn::Mpnet& mpnet() const { return mpnet_; }
  const nn::Ugnet& ugnet() const { return ugnet_; }

  // The windows as the networks last read them (oldest row first), for tests and tools.
  std::span<const float, nn::kMpnetWindowSize> mpnet_window() const { return mpnet_window_; }
  std::span<const float, nn::kUgnetWindowSize> ugnet_window() const { return ugnet_window_; }
  const BlendCounters& counters() const { return counters_; }
  // The networks' last outputs: MPNet's progression and UGNet's prediction for the next frame.
  const nn::Progression& progression() const { return progression_; }
  const EndEffectors& prediction() const { return prediction_; }
  float scale() const { return scale_; }

  // Bytes of per-person state (windows, counters, prediction), for docs/architecture.md.
  static constexpr std::size_t kStateBytes =
      sizeof(float) * (nn::kMpnetWindowSize + nn::kUgnetWindowSize + kEndEffectorSize) +
      sizeof(BlendCounters);

 private:
  void run_networks(std::span<const float> noise);
  void run_mpnet();
  void take_progression(const nn::Progression& progression);
  // Both begin_step()s: MPNet runs unless `known` gives its output.
  TranslationStep begin_step_with(const TranslationInput& frame, const nn::Progression* known);
  void push_user_row(const TranslationInput& frame);
  void push_avatar_row(const EndEffectors& avatar_x, const TargetFeature& target);

  nn::Mpnet mpnet_;
  nn::Ugnet ugnet_;
  float scale_;
  std::array<float, nn::kMpnetWindowSize> mpnet_window_{};
  std::array<float, nn::kUgnetWindowSize> ugnet_window_{};  // x ++ target ++ progression per row
  BlendCounters counters_;
  EndEffectors prediction_{};
  nn::Progression progression_{};
};

}  // namespace deixis
