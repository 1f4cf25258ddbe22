#include "gesture/translator_batch.h"

#include <algorithm>

namespace deixis {
namespace {

// v with at least n elements (grows only), as a span of exactly n.
template <typename T>
std::span<T> sized(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) {
    v.resize(n);
  }
  return {v.data(), n};
}

}  // namespace

void TranslatorBatch::reserve(std::size_t people, const nn::Mpnet& mpnet, const nn::Ugnet& ugnet) {
  pending_.reserve(people);
  group_.reserve(people);
  sized(taken_, people);
  sized(mpnet_windows_, people * nn::kMpnetWindowSize);
  sized(progressions_, people);
  sized(ugnet_windows_, people * nn::kUgnetWindowSize);
  if (ugnet.needs_noise()) {
    sized(noise_, people * nn::kDiffusionNoiseSize);
  }
  sized(predictions_, people * nn::kPoseSize);
  mpnet.reserve_batch(people, buffers_);
  ugnet.reserve_batch(people, buffers_);
}

void TranslatorBatch::add(Translator& translator) {
  pending_.push_back(&translator);
}

void TranslatorBatch::run() {
  // Groups of translators with the same weights (both networks), in order of first appearance;
  // quadratic in the number of groups, which is one or two (the hands' weight sets).
  const std::span<std::uint8_t> taken = sized(taken_, pending_.size());
  std::fill(taken.begin(), taken.end(), std::uint8_t{0});
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    if (taken[i] != 0) {
      continue;
    }
    const Translator& first = *pending_[i];
    group_.clear();
    for (std::size_t j = i; j < pending_.size(); ++j) {
      if (taken[j] == 0 && pending_[j]->mpnet().same_weights(first.mpnet()) &&
          pending_[j]->ugnet().same_weights(first.ugnet())) {
        taken[j] = 1;
        group_.push_back(pending_[j]);
      }
    }
    run_group(group_);
  }
  pending_.clear();
}

void TranslatorBatch::run_group(std::span<Translator* const> group) {
  const std::size_t n = group.size();
  const nn::Mpnet& mpnet = group.front()->mpnet();
  const nn::Ugnet& ugnet = group.front()->ugnet();

  const std::span<float> mpnet_windows = sized(mpnet_windows_, n * nn::kMpnetWindowSize);
  for (std::size_t i = 0; i < n; ++i) {
    std::ranges::copy(
        group[i]->mpnet_window(),
        mpnet_windows.begin() + static_cast<std::ptrdiff_t>(i * nn::kMpnetWindowSize));
  }
  const std::span<nn::MpnetOutput> progressions = sized(progressions_, n);
  mpnet.run_batch(mpnet_windows, progressions, buffers_);

  const bool noisy = ugnet.needs_noise();
  const std::span<float> ugnet_windows = sized(ugnet_windows_, n * nn::kUgnetWindowSize);
  const std::span<float> noise = sized(noise_, noisy ? n * nn::kDiffusionNoiseSize : 0);
  for (std::size_t i = 0; i < n; ++i) {
    group[i]->take_progression(progressions[i].progression);
    std::ranges::copy(
        group[i]->ugnet_window(),
        ugnet_windows.begin() + static_cast<std::ptrdiff_t>(i * nn::kUgnetWindowSize));
    if (noisy) {
      std::ranges::copy(group[i]->ugnet_noise(),
                        noise.begin() + static_cast<std::ptrdiff_t>(i * nn::kDiffusionNoiseSize));
    }
  }
  const std::span<float> predictions = sized(predictions_, n * nn::kPoseSize);
  ugnet.run_batch(ugnet_windows, noise, predictions, buffers_);
  for (std::size_t i = 0; i < n; ++i) {
    nn::PoseVector x;
    std::copy_n(predictions.begin() + static_cast<std::ptrdiff_t>(i * nn::kPoseSize), nn::kPoseSize,
                x.begin());
    group[i]->end_tick(x);
  }
}

void tick_translators(std::span<Translator* const> translators,
                      std::span<const TrackingFrame* const> frames, const LocalTargets& room,
                      TranslatorBatch& batch) {
  const std::size_t n = std::min(translators.size(), frames.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (translators[i]->begin_tick(frames[i], room)) {
      batch.add(*translators[i]);
    }
  }
  batch.run();
}

}  // namespace deixis
