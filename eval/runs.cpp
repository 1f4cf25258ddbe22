#include "eval/runs.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "eval/perturbation.h"

namespace deixis::eval {

namespace {

using dataset::Category;
constexpr int kRows = nn::kWindowRows;
constexpr std::array<Category, 2> kSingleTarget = {Category::kPointingSingle,
                                                   Category::kTouchingSingle};

// A reproducible stream per (seed, purpose, indices): runs do not depend on their order.
std::mt19937_64 stream(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0,
                       std::uint64_t c = 0) {
  std::seed_seq seq{seed, a, b, c};
  return std::mt19937_64(seq);
}

float scale_of(const TestSet& set) {
  return set.height() / kAvatarHeight;
}

// The diffusion UGNet's 30 Gaussian draws for one call (others read none).
std::span<const float> draws(const nn::Ugnet& ugnet, std::mt19937_64& rng,
                             std::vector<float>& buffer) {
  if (!ugnet.needs_noise()) {
    return {};
  }
  buffer.resize(nn::kDiffusionNoiseSize);
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (float& v : buffer) {
    v = n(rng);
  }
  return buffer;
}

// The loop's step at the pair's frame k, MPNet's output taken from `known` when it is given
// (user_progressions()).
TranslationStep begin_step(TranslationLoop& loop, const AlignedPair& pair, std::size_t k,
                           std::span<const nn::Progression> known) {
  return known.empty() ? loop.begin_step(pair.frames[k])
                       : loop.begin_step(pair.frames[k], known[k]);
}

EndEffectors to_x(std::span<const float, kEndEffectorSize> row) {
  EndEffectors x{};
  std::copy(row.begin(), row.end(), x.begin());
  return x;
}

// Avatar partners of the i-th of `list`: the next `partners` sequences cyclically (all of them,
// the sequence itself last, when `partners` is 0 or at least the list's size).
std::vector<std::size_t> partners_of(const std::vector<std::size_t>& list, std::size_t i,
                                     std::size_t partners) {
  const std::size_t n = list.size();
  const std::size_t count = partners == 0 ? n : std::min(partners, n);
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < count; ++k) {
    out.push_back(list[(i + 1 + k) % n]);
  }
  return out;
}

// The 18 columns FMD reads per frame (head 6D + position, hand 6D + position: x[3..20]).
constexpr int kMotionFirst = ee::kHeadForward;

// 30-frame segments with a hop of 15 plus the last 30 frames, encoded
// (docs/eval.md#what-each-number-is).
void encode_segments(const nn::MotionEncoder& encoder, const std::vector<EndEffectors>& motion,
                     std::vector<std::vector<double>>& codes) {
  const std::size_t n = motion.size();
  constexpr auto kFrames = static_cast<std::size_t>(nn::kMotionSegmentFrames);
  if (n < kFrames) {
    return;
  }
  std::vector<std::size_t> starts;
  for (std::size_t s = 0; s + kFrames <= n; s += kFrames / 2) {
    starts.push_back(s);
  }
  starts.push_back(n - kFrames);
  std::array<float, nn::kMotionSegmentSize> segment{};
  for (const std::size_t s : starts) {
    for (std::size_t f = 0; f < kFrames; ++f) {
      std::copy_n(motion[s + f].begin() + kMotionFirst, nn::kMotionChannels,
                  segment.begin() + static_cast<std::ptrdiff_t>(f * nn::kMotionChannels));
    }
    const nn::MotionCode code = encoder.run(segment);
    codes.emplace_back(code.begin(), code.end());
  }
}

}  // namespace

std::vector<std::size_t> selected(const TestSet& set, Category category, const Sampling& sampling) {
  std::vector<std::size_t> list = set.of_category(category);
  if (sampling.per_category != 0 && list.size() > sampling.per_category) {
    list.resize(sampling.per_category);
  }
  return list;
}

// ---- MPNet ---------------------------------------------------------------------------------

MpeResult run_mpe(const nn::Mpnet& mpnet, const TestSet& set, const Sampling& sampling) {
  MpeResult r;
  const dataset::Dataset& d = set.data();
  for (const Category c : dataset::kAllCategories) {
    for (const std::size_t s : selected(set, c, sampling)) {
      const std::span<const float> rows(d.mpnet_features.data() + d.begin(s) * kMpnetFeatureCount,
                                        set.length(s) * kMpnetFeatureCount);
      const std::vector<dataset::Labels> p = predict_progressions(mpnet, rows);
      MpeSum sum;
      for (std::size_t k = 0; k < p.size(); ++k) {
        const std::array<float, 3> label = set.labels(s, k);
        for (int ch = 0; ch < 3; ++ch) {
          sum.error[static_cast<std::size_t>(ch)] +=
              std::abs(static_cast<double>(p[k][static_cast<std::size_t>(ch)]) -
                       static_cast<double>(label[static_cast<std::size_t>(ch)]));
        }
        ++sum.frames;
      }
      r.categories[static_cast<std::size_t>(c)].add(sum);
      r.all.add(sum);
    }
  }
  return r;
}

Mean run_state_stability(const nn::Mpnet& mpnet, const TestSet& set, const Sampling& sampling) {
  Mean m;
  std::array<float, nn::kMpnetWindowSize> window{};
  for (const Category c : {Category::kPointingTwoTargets, Category::kTouchingTwoTargets}) {
    for (const std::size_t s : selected(set, c, sampling)) {
      const auto first = set.features(s, 0);
      const auto last = set.features(s, set.length(s) - 1);
      for (int step = 0; step < kRows; ++step) {
        // Rows 0 … 28 − step hold the first row, the newest step + 1 rows the last.
        for (int r = 0; r < kRows; ++r) {
          const auto& src = r >= kRows - 1 - step ? last : first;
          std::copy(src.begin(), src.end(), window.begin() + r * kMpnetFeatureCount);
        }
        const nn::Progression p = mpnet.run(window).progression;
        m.add((std::abs(static_cast<double>(p[0])) + std::abs(static_cast<double>(p[1])) +
               std::abs(1.0 - static_cast<double>(p[2]))) /
              3.0);
      }
    }
  }
  return m;
}

// ---- the chained loop ----------------------------------------------------------------------

std::vector<EndEffectors> run_chain(const Generator& g, const AlignedPair& pair, float scale,
                                    std::uint64_t seed,
                                    std::span<const nn::Progression> progressions) {
  std::vector<EndEffectors> out;
  out.reserve(pair.frames.size());
  if (g.copy_paste()) {
    for (const TranslationInput& f : pair.frames) {
      out.push_back(f.user_x);
    }
    return out;
  }
  std::mt19937_64 rng = stream(seed, 0x636861696e);
  std::vector<float> buffer;
  TranslationLoop loop(*g.mpnet, *g.ugnet, scale);
  loop.reset(pair.frames.front(), pair.avatar_initial, draws(*g.ugnet, rng, buffer));
  out.push_back(loop.prediction());
  for (std::size_t k = 0; k + 1 < pair.frames.size(); ++k) {
    TranslationStep step = begin_step(loop, pair, k, progressions);
    const std::span<const float> noise = draws(*g.ugnet, rng, buffer);
    loop.end_step(g.ugnet->run(loop.ugnet_window(), noise), step);
    out.push_back(step.prediction);
  }
  return out;
}

std::vector<nn::Progression> user_progressions(const nn::Mpnet& mpnet, const AlignedPair& pair) {
  // The loop's MPNet window at step k is the last 30 of [f0 × 30, f0 … fk]: MPE's windows
  // (predict_progressions) over the steps' rows f0 … f(n−2).
  std::vector<float> rows;
  for (std::size_t k = 0; k + 1 < pair.frames.size(); ++k) {
    rows.insert(rows.end(), pair.frames[k].user_features.begin(),
                pair.frames[k].user_features.end());
  }
  return predict_progressions(mpnet, rows);  // Labels are progressions
}

std::vector<std::vector<EndEffectors>> run_chains(
    const Generator& g, std::span<const AlignedPair> pairs, float scale,
    std::span<const std::uint64_t> seeds,
    std::span<const std::span<const nn::Progression>> progressions) {
  const auto known = [&](std::size_t i) {
    return progressions.empty() ? std::span<const nn::Progression>() : progressions[i];
  };
  std::vector<std::vector<EndEffectors>> out;
  out.reserve(pairs.size());
  if (g.copy_paste() || !g.ugnet->gains_from_batch()) {
    // Only the diffusion and Transformer UGNets gain from the batch (their products become
    // matrix–matrix over many windows); the MoE and MLP run window by window either way.
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      out.push_back(run_chain(g, pairs[i], scale, seeds[i], known(i)));
    }
    return out;
  }
  // run_chain()'s steps, chain by chain, with UGNet's calls of one frame gathered.
  std::vector<TranslationLoop> loops;
  std::vector<std::mt19937_64> rngs;
  std::vector<float> buffer;
  loops.reserve(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    rngs.push_back(stream(seeds[i], 0x636861696e));
    loops.emplace_back(*g.mpnet, *g.ugnet, scale);
    loops[i].reset(pairs[i].frames.front(), pairs[i].avatar_initial,
                   draws(*g.ugnet, rngs[i], buffer));
    out.emplace_back().reserve(pairs[i].frames.size());
    out[i].push_back(loops[i].prediction());
  }
  std::vector<std::size_t> active;
  std::vector<TranslationStep> steps;
  std::vector<float> windows, noise, predictions;
  for (std::size_t k = 0;; ++k) {
    active.clear();
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (k + 1 < pairs[i].frames.size()) {
        active.push_back(i);
      }
    }
    if (active.empty()) {
      return out;
    }
    steps.resize(active.size());
    windows.resize(active.size() * nn::kUgnetWindowSize);
    noise.resize(active.size() * nn::kDiffusionNoiseSize);
    predictions.resize(active.size() * nn::kPoseSize);
    for (std::size_t a = 0; a < active.size(); ++a) {
      const std::size_t i = active[a];
      steps[a] = begin_step(loops[i], pairs[i], k, known(i));
      std::ranges::copy(loops[i].ugnet_window(), windows.begin() + a * nn::kUgnetWindowSize);
      std::ranges::copy(draws(*g.ugnet, rngs[i], buffer),
                        noise.begin() + a * nn::kDiffusionNoiseSize);
    }
    g.ugnet->run_batch(windows, noise, predictions);
    for (std::size_t a = 0; a < active.size(); ++a) {
      nn::PoseVector x;
      std::copy_n(predictions.begin() + a * nn::kPoseSize, nn::kPoseSize, x.begin());
      loops[active[a]].end_step(x, steps[a]);
      out[active[a]].push_back(steps[a].prediction);
    }
  }
}

PointingError dip_pointing(const EndEffectors& x, const Vec3& target_in_root) {
  return pointing_error(deictic_chain(x), target_in_root);
}

DipResult run_dip(const Generator& g, const TestSet& set, const Sampling& sampling) {
  DipResult r;
  for (const Category c : kSingleTarget) {
    // A category's pairs are chained together (run_chains), then measured in order.
    std::vector<AlignedPair> pairs;
    std::vector<std::uint64_t> seeds;
    const std::vector<std::size_t> list = selected(set, c, sampling);
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (const std::size_t j : partners_of(list, i, sampling.dip_partners)) {
        std::optional<AlignedPair> pair = align_at_completion(set, list[i], j);
        if (!pair) {
          ++r.skipped;
          continue;
        }
        pairs.push_back(std::move(*pair));
        seeds.push_back(sampling.seed ^ (list[i] * 1000 + j));
      }
    }
    const std::vector<std::vector<EndEffectors>> x = run_chains(g, pairs, scale_of(set), seeds);
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      const DeicticChain chain = deictic_chain(x[p].back());
      if (dataset::is_touching(c)) {
        r.pe.add(touching_error_cm(chain, pairs[p].avatar_target));
      } else {
        const PointingError e = pointing_error(chain, pairs[p].avatar_target);
        r.he.add(e.horizontal_deg);
        r.ve.add(e.vertical_deg);
      }
    }
  }
  return r;
}

// ---- DR ------------------------------------------------------------------------------------

namespace {

// One abrupt change: UGNet alone from completion pose x0 (target t0) to the new target, 30
// steps, progression (1, 1, 0) throughout; adds the per-step errors
// (docs/eval.md#what-each-number-is).
void dr_change(const nn::Ugnet* ugnet, const EndEffectors& x0, const TargetFeature& t0,
               const TargetFeature& t_new, const Vec3& target, bool touching, std::uint64_t seed,
               DrResult& r) {
  std::array<float, nn::kUgnetWindowSize> window{};
  const std::array<float, 3> completed = {1.0f, 1.0f, 0.0f};
  for (int row = 0; row < kRows; ++row) {
    float* at = window.data() + row * nn::kUgnetColumns;
    std::copy(x0.begin(), x0.end(), at);
    const TargetFeature& t = row == kRows - 1 ? t_new : t0;
    std::copy(t.begin(), t.end(), at + nn::kPoseSize);
    std::copy(completed.begin(), completed.end(), at + nn::kPoseSize + kTargetFeatureSize);
  }
  std::mt19937_64 rng = stream(seed, 0x6472);
  std::vector<float> buffer;
  EndEffectors x = x0;
  for (int step = 0; step < kRows; ++step) {
    if (ugnet) {
      x = ugnet->run(window, draws(*ugnet, rng, buffer));
    }
    const DeicticChain chain = deictic_chain(x);
    if (touching) {
      r.pl.add(touching_error_cm(chain, target));
    } else {
      const PointingError e = pointing_error(chain, target);
      r.hl.add(e.horizontal_deg);
      r.vl.add(e.vertical_deg);
    }
    // Shift: the new row keeps the new target; its pose is the output (only it is read).
    std::copy(window.begin() + nn::kUgnetColumns, window.end(), window.begin());
    float* newest = window.data() + (kRows - 1) * nn::kUgnetColumns;
    std::copy(x.begin(), x.end(), newest);
    std::copy(t_new.begin(), t_new.end(), newest + nn::kPoseSize);
  }
}

struct CompletionState {
  std::size_t sequence;
  EndEffectors x;
  TargetFeature target_feature;
  Vec3 target;
};

std::vector<CompletionState> completion_states(const TestSet& set, Category c,
                                               const Sampling& sampling) {
  std::vector<CompletionState> out;
  for (const std::size_t s : selected(set, c, sampling)) {
    const auto onset = first_key(set, s);
    const auto done = onset ? completion_frame(set, s, *onset) : std::nullopt;
    if (!done) {
      continue;
    }
    TargetFeature t{};
    const auto tf = set.target_feature(s, *done);
    std::copy(tf.begin(), tf.end(), t.begin());
    out.push_back({s, to_x(set.end_effectors(s, *done)), t, set.hand_target_in_root(s, *done)});
  }
  return out;
}

}  // namespace

DrResult run_dr(const nn::Ugnet* ugnet, const TestSet& set, const Sampling& sampling) {
  DrResult r;
  for (const Category c : kSingleTarget) {
    const bool touching = dataset::is_touching(c);
    const std::vector<CompletionState> states = completion_states(set, c, sampling);
    const std::size_t targets =
        touching ? sampling.dr_targets_touching : sampling.dr_targets_pointing;
    const std::size_t starts =
        sampling.dr_starts == 0 ? states.size() : std::min(sampling.dr_starts, states.size());
    for (std::size_t i = 0; i < starts; ++i) {
      for (std::size_t k = 1; k < states.size() && k <= targets; ++k) {
        const CompletionState& to = states[(i + k) % states.size()];
        dr_change(ugnet, states[i].x, states[i].target_feature, to.target_feature, to.target,
                  touching, sampling.seed ^ (i * 131 + k), r);
      }
    }
  }
  return r;
}

// ---- FMD -----------------------------------------------------------------------------------

std::vector<double> run_fmd(const Generator& g, const nn::MotionEncoder& encoder,
                            const TestSet& set, const Sampling& sampling, FmdReuse reuse) {
  // A trial draws every sequence's partner at random, so over ten trials pairs recur (≈ 22 % of
  // the chains of a full test subject, most in the categories of 8 sequences), and the
  // Transformer UGNet's chains are most of the evaluation's time (docs/eval.md).
  const bool reuse_all = reuse == FmdReuse::kOn;
  const bool noise_free = g.copy_paste() || !g.ugnet->needs_noise();
  using Codes = std::vector<std::vector<double>>;
  std::map<std::size_t, Codes> real_of;                                 // by user sequence
  std::map<std::pair<std::size_t, std::size_t>, Codes> generated_of;    // by (user, partner)
  std::map<std::size_t, std::vector<nn::Progression>> progressions_of;  // by user sequence
  std::vector<double> trials;
  for (int trial = 0; trial < sampling.fmd_trials; ++trial) {
    if (!reuse_all) {
      real_of.clear();
      generated_of.clear();
    }
    std::mt19937_64 rng = stream(sampling.seed, 0x666d64, static_cast<std::uint64_t>(trial));
    Codes real, generated;
    for (const Category c : dataset::kAllCategories) {
      const std::vector<std::size_t> list = selected(set, c, sampling);
      if (list.empty()) {
        continue;
      }
      // Every user's partner and seed are drawn whether or not its chain runs, so the draws of
      // later pairs (and a diffusion UGNet's noise) do not depend on what was reused.
      std::uniform_int_distribution<std::size_t> pick(0, list.size() - 1);
      std::vector<std::pair<std::size_t, std::size_t>> keys;
      std::vector<AlignedPair> pairs;
      std::vector<std::uint64_t> seeds;
      std::vector<std::size_t> chained_key;  // keys[chained_key[p]] is pairs[p]
      for (const std::size_t user : list) {
        keys.emplace_back(user, list[pick(rng)]);
        const std::uint64_t seed = rng();
        if (noise_free && generated_of.contains(keys.back())) {
          continue;
        }
        pairs.push_back(align_whole(set, user, keys.back().second));
        seeds.push_back(seed);
        chained_key.push_back(keys.size() - 1);
      }
      // MPNet's outputs along a user's rows, whatever the partner.
      std::vector<std::span<const nn::Progression>> progressions;
      if (reuse_all && !g.copy_paste()) {
        for (std::size_t p = 0; p < pairs.size(); ++p) {
          const std::size_t user = keys[chained_key[p]].first;
          auto at = progressions_of.find(user);
          if (at == progressions_of.end()) {
            at = progressions_of.emplace(user, user_progressions(*g.mpnet, pairs[p])).first;
          }
          progressions.emplace_back(at->second);
        }
      }
      const std::vector<std::vector<EndEffectors>> chained =
          run_chains(g, pairs, scale_of(set), seeds, progressions);
      std::vector<Codes> fresh(keys.size());
      for (std::size_t p = 0; p < pairs.size(); ++p) {
        const std::size_t user = keys[chained_key[p]].first;
        if (!real_of.contains(user)) {
          std::vector<EndEffectors> motion;
          for (const TranslationInput& f : pairs[p].frames) {
            motion.push_back(f.user_x);
          }
          encode_segments(encoder, motion, real_of[user]);
        }
        encode_segments(encoder, chained[p], fresh[chained_key[p]]);
      }
      // In the list's order, as without reuse (the covariances' sums in the same order).
      for (std::size_t k = 0; k < keys.size(); ++k) {
        const Codes& r = real_of.at(keys[k].first);
        real.insert(real.end(), r.begin(), r.end());
        // Only a noise-free generator's pairs are kept, and a kept pair was not chained again.
        const auto known = generated_of.find(keys[k]);
        const Codes& codes = known != generated_of.end() ? known->second : fresh[k];
        generated.insert(generated.end(), codes.begin(), codes.end());
        if (noise_free && known == generated_of.end()) {
          generated_of.emplace(keys[k], std::move(fresh[k]));
        }
      }
    }
    if (real.size() >= 2 && generated.size() >= 2) {
      trials.push_back(frechet_distance(real, generated));
    }
  }
  return trials;
}

// ---- Robustness ----------------------------------------------------------------------------

void DeviationMean::add(const MotionDeviation& d) {
  position_cm.add(d.position_cm);
  rotation_deg.add(d.rotation_deg);
  linear_velocity_cm_s.add(d.linear_velocity_cm_s);
  angular_velocity_deg_s.add(d.angular_velocity_deg_s);
}

RobustnessResult run_robustness(const Generator& g, const TestSet& set, const Sampling& sampling) {
  RobustnessResult r;
  const float scale = scale_of(set);
  for (const Category c : dataset::kAllCategories) {
    const std::vector<std::size_t> list = selected(set, c, sampling);
    for (std::size_t i = 0; i < list.size(); ++i) {
      for (const std::size_t j : partners_of(list, i, sampling.robustness_partners)) {
        const std::uint64_t pair_seed = sampling.seed ^ (list[i] * 1000 + j);
        std::mt19937_64 rng = stream(pair_seed, 0x726f62);
        const AlignedPair clean = align_whole(set, list[i], j);
        const std::vector<EndEffectors> reference = run_chain(g, clean, scale, pair_seed);
        for (std::size_t d = 0; d < kMissedFrames.size(); ++d) {
          // The same drop points for every duration (common random numbers), so the curve of
          // Fig. 5 shows the duration's effect rather than which points happened to drop.
          std::mt19937_64 drops = stream(pair_seed, 0x6d6973);
          AlignedPair noisy = clean;
          apply_missed_tracking(noisy.frames, kMissedFrames[d], drops);
          r.missed[d].add(motion_deviation(reference, run_chain(g, noisy, scale, pair_seed)));
        }
        // Jitter and noise perturb the tracking; their clean run recomputes the rows from the
        // unperturbed tracking the same way.
        const std::size_t onset = first_key(set, list[i]).value_or(0);
        AlignedPair recomputed = clean;
        recompute_user_rows(set, list[i], onset, Perturbation::kNone, rng, recomputed.frames);
        const std::vector<EndEffectors> base = run_chain(g, recomputed, scale, pair_seed);
        for (const Perturbation p : {Perturbation::kJitter, Perturbation::kContinuousNoise}) {
          AlignedPair noisy = clean;
          recompute_user_rows(set, list[i], onset, p, rng, noisy.frames);
          (p == Perturbation::kJitter ? r.jitter : r.noise)
              .add(motion_deviation(base, run_chain(g, noisy, scale, pair_seed)));
        }
      }
    }
  }
  return r;
}

}  // namespace deixis::eval
