#pragma once
// Many translators' ticks with their networks run as batches (nn/batch.h): one site tick
// translates every remote person together. Each translator ticks as it would alone
// (Translator::begin_tick … end_tick); only MPNet and UGNet run once per group of translators
// sharing the same weights (people of one deictic hand share a pair), each as one batch. The
// results are those of ticking each translator alone, bit for bit (nn/batch.h;
// tests/gesture/translator_batch_test.cpp).

#include <cstdint>
#include <span>
#include <vector>

#include "gesture/nn/batch.h"
#include "gesture/translator.h"

namespace deixis {

// The working memory of batched ticks. Allocates nothing once it has run a batch of this many
// people (or after reserve()); one TranslatorBatch serves one thread.
class TranslatorBatch {
 public:
  TranslatorBatch() = default;
  // Sizes everything for `people` translators running `mpnet` and `ugnet`.
  void reserve(std::size_t people, const nn::Mpnet& mpnet, const nn::Ugnet& ugnet);

  // Queues a translator whose begin_tick() returned true this tick.
  void add(Translator& translator);
  // Completes every queued tick, the networks grouped by weights, one batch per group; the queue
  // is empty afterwards.
  void run();

 private:
  void run_group(std::span<Translator* const> group);

  std::vector<Translator*> pending_;
  std::vector<Translator*> group_;
  std::vector<std::uint8_t> taken_;
  std::vector<float> mpnet_windows_;
  std::vector<nn::MpnetOutput> progressions_;
  std::vector<float> ugnet_windows_;
  std::vector<float> noise_;
  std::vector<float> predictions_;
  nn::BatchBuffers buffers_;
};

// tick() of every translator, their networks batched: translators[i] gets frames[i] (null: no
// frame this tick); each one's result is its tick_result(). Both spans have one size (extra
// entries of the longer are ignored).
void tick_translators(std::span<Translator* const> translators,
                      std::span<const TrackingFrame* const> frames, const LocalTargets& room,
                      TranslatorBatch& batch);

}  // namespace deixis
