#pragma once
// The tracking failures of paper §V.D, applied to a user's recorded sequence.
//
// - Missed tracking, as the authors' test_UGNet.py does it (docs/eval.md#what-each-number-is):
//   at frames 0, 30, 60, … with probability 0.3 the next `frames` rows are replaced by the row
//   before (the system holds the last tracked frame).
// - Jitter (occlusion) and continuous noise are not in the authors' release; ours perturb the
//   tracking (head, the deictic wrist with its fingertip, gaze) and the network columns are
//   recomputed by gesture/features.h, as the runtime would. Jitter: on 3 % of frames (about one a
//   second) one part jumps by 5–15 cm and 10–30° for that frame. Continuous noise: every frame,
//   σ = 1 cm per axis and 2° per axis on head and wrist, 1° on gaze.

#include <cstdint>
#include <random>
#include <vector>

#include "eval/test_set.h"
#include "gesture/translation_loop.h"

namespace deixis::eval {

enum class Perturbation { kNone, kJitter, kContinuousNoise };

// The user's rows of `frames` (features and end-effectors) replaced by the row before at the
// authors' drop points; returns how many rows were held.
std::size_t apply_missed_tracking(std::vector<TranslationInput>& frames, int drop_frames,
                                  std::mt19937_64& rng);

// The user's features and end-effectors of frames [0, count) recomputed from sequence s's
// tracking from frame `first` on, perturbed as `kind` says (kNone: recomputed as recorded).
void recompute_user_rows(const TestSet& set, std::size_t s, std::size_t first, Perturbation kind,
                         std::mt19937_64& rng, std::vector<TranslationInput>& frames);

}  // namespace deixis::eval
