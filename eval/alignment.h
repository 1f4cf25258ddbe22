#pragma once
// Pairing a user's sequence with an avatar's (another sequence of the same category: its targets
// become the avatar's targets) and aligning them in time, as the authors' data_parser.py does
// for their evaluation (docs/eval.md#what-each-number-is): rows before the first phase key are
// dropped, and phases are aligned by PCHIP-resampling the shorter of the two to the longer.
//
// The capture marks the start and end of every label ramp as a phase key (docs/dataset.md), more
// keys than the authors' pairing files, and not always the same number in two sequences of a
// category. So DIP aligns the one phase its metric depends on: movement onset (the first key) to
// the completion state (the first frame whose deictic label is 1), then continues with the rows
// after it unresampled (docs/decisions.md, "DIP phase alignment").

#include <optional>
#include <vector>

#include "eval/test_set.h"
#include "gesture/translation_loop.h"

namespace deixis::eval {

// Rows the authors' DIP reads after the completion state: the sequence is cut at (first phase)
// + 40 rows including the 30-row prefix, i.e. 10 frames after the completion key.
inline constexpr int kRowsAfterCompletion = 10;

struct AlignedPair {
  std::vector<TranslationInput> frames;  // user features and x, avatar target feature
  EndEffectors avatar_initial{};         // the avatar sequence's pose at its first aligned row
  Vec3 avatar_target = Vec3::Zero();     // avatar's hand target at the last row (root O, network)
  std::size_t completion = 0;            // index of the completion-state row in `frames`
};

// First phase key of sequence s (movement onset), or nullopt when it has none.
std::optional<std::size_t> first_key(const TestSet& set, std::size_t s);
// First frame at or after `from` whose deictic label is 1 (completion state), or nullopt.
std::optional<std::size_t> completion_frame(const TestSet& set, std::size_t s, std::size_t from);

// DIP pairing (docs/eval.md#what-each-number-is): onset → completion of both sequences aligned (the
// shorter phase PCHIP-resampled to the longer), then `after` more rows of each. nullopt when either
// sequence has no onset or never completes.
std::optional<AlignedPair> align_at_completion(const TestSet& set, std::size_t user,
                                               std::size_t avatar,
                                               int after = kRowsAfterCompletion);

// FMD and robustness pairing: the user's rows from the first key to the end as recorded (their
// motion is the "real" motion and the one perturbed, so it is never resampled); the avatar's
// target rows are warped onto the user's time line phase by phase when both sequences have the
// same number of phase keys, else as a whole. `avatar_target` is the avatar's at the last row.
AlignedPair align_whole(const TestSet& set, std::size_t user, std::size_t avatar);

// `count` rows (each `width` floats) PCHIP-resampled from rows [first, last] of `rows`
// (inclusive, uniformly spaced) to `count` uniformly spaced rows over the same span.
std::vector<float> resample_rows(std::span<const float> rows, int width, std::size_t first,
                                 std::size_t last, std::size_t count);

}  // namespace deixis::eval
