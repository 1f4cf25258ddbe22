#pragma once
// The evaluation runs of paper §V on one held-out subject (docs/eval.md#what-each-number-is): each
// runs a row's networks over the subject's test set the way the authors' test scripts do and
// returns the subject's numbers; eval/evaluation.h averages subjects and lays out the tables.
//
//   MPE, SS    MPNet alone (test_MPNet.py)
//   DIP        the chained loop MPNet → window → blend → UGNet on aligned pairs, read at the
//              completion state
//   DR         UGNet alone from completion poses after an abrupt target change
//   FMD        the chained loop on whole sequences, latent codes of the motion encoder
//   robustness missed tracking 0.2–1.0 s, jitter and continuous noise against the clean run
//
// A Generator without a UGNet is the copy-paste baseline: the avatar takes the user's
// end-effectors unchanged (the user's pose relative to their own root, put at the avatar's).

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "eval/alignment.h"
#include "eval/judge.h"
#include "eval/metrics.h"
#include "eval/test_set.h"
#include "gesture/nn/motion_encoder.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"

namespace deixis::eval {

// How much of a test set each run reads. Zero means "all" (the paper's protocol); --quick and
// the time budget of the full run set smaller numbers (docs/eval.md).
struct Sampling {
  std::size_t per_category = 0;          // sequences per category and subject
  std::size_t dip_partners = 0;          // avatar sequences per user sequence (authors: all)
  std::size_t dr_starts = 0;             // completion poses per gesture (authors: 1 hard-coded)
  std::size_t dr_targets_pointing = 14;  // new targets per start (authors: 14 and 29)
  std::size_t dr_targets_touching = 29;
  std::size_t robustness_partners = 1;  // avatar sequences per user sequence
  int fmd_trials = 10;
  std::uint64_t seed = 1;
};

// The networks of one row for the subject's hand. No UGNet: the copy-paste baseline.
struct Generator {
  const nn::Mpnet* mpnet = nullptr;
  const nn::Ugnet* ugnet = nullptr;
  bool copy_paste() const { return ugnet == nullptr; }
};

// A running mean.
struct Mean {
  double sum = 0.0;
  std::size_t count = 0;
  void add(double v) {
    sum += v;
    ++count;
  }
  std::optional<double> value() const {
    return count ? std::optional<double>(sum / static_cast<double>(count)) : std::nullopt;
  }
};

// The sequences of a category a run reads (the first `per_category`, in file order).
std::vector<std::size_t> selected(const TestSet& set, dataset::Category category,
                                  const Sampling& sampling);

// ---- MPNet ---------------------------------------------------------------------------------

struct MpeResult {
  std::array<MpeSum, dataset::kCategoryCount> categories;
  MpeSum all;
};
MpeResult run_mpe(const nn::Mpnet& mpnet, const TestSet& set, const Sampling& sampling);

// SS on the subject's two-target sequences (the authors used their training subject's; no number
// may come from it): 30 windows in which the first row gives way to the last row, one row
// per step; mean |p − (0, 0, 1)| over steps and channels.
Mean run_state_stability(const nn::Mpnet& mpnet, const TestSet& set, const Sampling& sampling);

// ---- DIP -----------------------------------------------------------------------------------

struct DipResult {
  Mean he, ve, pe;          // degrees, degrees, centimetres
  std::size_t skipped = 0;  // pairs without an onset or completion state
};
DipResult run_dip(const Generator& generator, const TestSet& set, const Sampling& sampling);

// ---- DR ------------------------------------------------------------------------------------

struct DrResult {
  Mean hl, vl, pl;  // °/frame, °/frame, cm/frame
};
// `ugnet` null: copy-paste (the avatar holds the pose it had before the target moved).
DrResult run_dr(const nn::Ugnet* ugnet, const TestSet& set, const Sampling& sampling);

// ---- FMD -----------------------------------------------------------------------------------

// Whether run_fmd() reuses what does not change from one trial to the next: the codes of a
// user's own motion (the real side: its recorded rows, whatever the partner) and MPNet's outputs
// along them, and for a generator without noise the codes of a pair drawn again (its chain is the
// same). The figures are the same either way (up to float rounding for the batched Transformer,
// whose batches differ); off only to test that.
enum class FmdReuse { kOn, kOff };

// One FMD per trial (each trial pairs every sequence with a random one of its category).
std::vector<double> run_fmd(const Generator& generator, const nn::MotionEncoder& encoder,
                            const TestSet& set, const Sampling& sampling,
                            FmdReuse reuse = FmdReuse::kOn);

// ---- Robustness ----------------------------------------------------------------------------

inline constexpr std::array<int, 5> kMissedFrames = {6, 12, 18, 24, 30};  // 0.2 … 1.0 s

struct DeviationMean {
  Mean position_cm, rotation_deg, linear_velocity_cm_s, angular_velocity_deg_s;
  void add(const MotionDeviation& d);
};
struct RobustnessResult {
  std::array<DeviationMean, kMissedFrames.size()> missed;
  DeviationMean jitter;
  DeviationMean noise;
};
RobustnessResult run_robustness(const Generator& generator, const TestSet& set,
                                const Sampling& sampling);

// ---- building blocks (tests use them) -------------------------------------------------------

// The chained loop over an aligned pair (docs/conventions.md#translation-loop): for each frame k,
// UGNet's prediction of the avatar's end-effectors at frame k from the windows ending at frame
// k − 1 (frame 0: the 30-row prefix). The copy-paste generator returns the user's end-effectors.
// `seed` feeds the diffusion UGNet's draws.
// `progressions`, when given, are MPNet's outputs for the chain's steps (user_progressions()),
// so MPNet does not run again.
std::vector<EndEffectors> run_chain(const Generator& generator, const AlignedPair& pair,
                                    float scale, std::uint64_t seed,
                                    std::span<const nn::Progression> progressions = {});

// run_chain() on pairs[i] with seeds[i], for every i. With a diffusion or Transformer UGNet
// (nn::Ugnet::gains_from_batch) the chains advance in lockstep and UGNet runs all their windows of
// a frame as one batch (nn::Ugnet::run_batch; matrix–matrix products), each chain keeping its own
// draws; the results equal run_chain()'s up to float rounding. Other generators run the pairs one
// after the other.
std::vector<std::vector<EndEffectors>> run_chains(
    const Generator& generator, std::span<const AlignedPair> pairs, float scale,
    std::span<const std::uint64_t> seeds,
    std::span<const std::span<const nn::Progression>> progressions = {});

// MPNet's outputs along a pair's chain, step by step: they read the user's rows only, so pairs
// with the same user rows (FMD's, whatever the partner) share them.
std::vector<nn::Progression> user_progressions(const nn::Mpnet& mpnet, const AlignedPair& pair);

// HE/VE (pointing) or PE (touching) of the chain's prediction for the pair's last frame.
PointingError dip_pointing(const EndEffectors& x, const Vec3& target_in_root);

}  // namespace deixis::eval
