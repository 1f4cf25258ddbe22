#include "eval/alignment.h"

#include <algorithm>

#include "dataset/pchip.h"

namespace deixis::eval {

namespace {

// Completion: the deictic label at 1 (labels are exact, docs/dataset.md).
constexpr float kCompleted = 1.0f - 1e-6f;

template <std::size_t N>
std::array<float, N> row_at(const std::vector<float>& rows, std::size_t i) {
  std::array<float, N> out{};
  std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(i * N), N, out.begin());
  return out;
}

// The columns of the frames a pair is built from, for rows [first, last] of one sequence
// resampled to `count` rows (absolute row indices into the dataset's tensors).
struct Columns {
  std::vector<float> features, x, target;
};
Columns resampled(const dataset::Dataset& d, std::size_t first, std::size_t last,
                  std::size_t count) {
  return {resample_rows(d.mpnet_features, kMpnetFeatureCount, first, last, count),
          resample_rows(d.end_effectors, kEndEffectorSize, first, last, count),
          resample_rows(d.target_feature, kTargetFeatureSize, first, last, count)};
}

// Appends rows [0, count) of user columns `u` and avatar target columns `a` to `pair.frames`.
void append_frames(const Columns& u, const Columns& a, std::size_t count, AlignedPair& pair) {
  for (std::size_t i = 0; i < count; ++i) {
    TranslationInput in;
    in.user_features = row_at<kMpnetFeatureCount>(u.features, i);
    in.user_x = row_at<kEndEffectorSize>(u.x, i);
    in.avatar_target = row_at<kTargetFeatureSize>(a.target, i);
    pair.frames.push_back(in);
  }
}

// Phase keys of sequence s from `from` on (local frame indices, ascending, without repeats),
// then the last frame, so consecutive entries bound the phases.
std::vector<std::size_t> phase_bounds(const TestSet& set, std::size_t s, std::size_t from) {
  std::vector<std::size_t> bounds;
  for (std::size_t k = from; k < set.length(s); ++k) {
    if (set.phase_key(s, k) || k == from) {
      bounds.push_back(k);
    }
  }
  if (bounds.back() != set.length(s) - 1) {
    bounds.push_back(set.length(s) - 1);
  }
  return bounds;
}

}  // namespace

std::vector<float> resample_rows(std::span<const float> rows, int width, std::size_t first,
                                 std::size_t last, std::size_t count) {
  const auto w = static_cast<std::size_t>(width);
  std::vector<float> out(count * w);
  const std::size_t n = last - first + 1;
  std::vector<double> column(n);
  for (std::size_t c = 0; c < w; ++c) {
    for (std::size_t i = 0; i < n; ++i) {
      column[i] = static_cast<double>(rows[(first + i) * w + c]);
    }
    const std::vector<double> values =
        n == 1 ? std::vector<double>(count, column[0]) : dataset::pchip_resample(column, count);
    for (std::size_t i = 0; i < count; ++i) {
      out[i * w + c] = static_cast<float>(values[i]);
    }
  }
  return out;
}

std::optional<std::size_t> first_key(const TestSet& set, std::size_t s) {
  for (std::size_t k = 0; k < set.length(s); ++k) {
    if (set.phase_key(s, k)) {
      return k;
    }
  }
  return std::nullopt;
}

std::optional<std::size_t> completion_frame(const TestSet& set, std::size_t s, std::size_t from) {
  for (std::size_t k = from; k < set.length(s); ++k) {
    if (set.labels(s, k)[1] >= kCompleted) {
      return k;
    }
  }
  return std::nullopt;
}

std::optional<AlignedPair> align_at_completion(const TestSet& set, std::size_t user,
                                               std::size_t avatar, int after) {
  const auto onset_u = first_key(set, user);
  const auto onset_a = first_key(set, avatar);
  if (!onset_u || !onset_a) {
    return std::nullopt;
  }
  const auto done_u = completion_frame(set, user, *onset_u);
  const auto done_a = completion_frame(set, avatar, *onset_a);
  if (!done_u || !done_a) {
    return std::nullopt;
  }
  const dataset::Dataset& d = set.data();
  const std::size_t bu = d.begin(user), ba = d.begin(avatar);
  // Phase 1, onset → completion inclusive, both at the longer length.
  const std::size_t phase = std::max(*done_u - *onset_u, *done_a - *onset_a) + 1;
  AlignedPair pair;
  append_frames(resampled(d, bu + *onset_u, bu + *done_u, phase),
                resampled(d, ba + *onset_a, ba + *done_a, phase), phase, pair);
  pair.completion = phase - 1;
  // The hold after it as recorded (the last frame repeats if a sequence ends sooner).
  std::size_t last_a = *done_a;
  for (int i = 1; i <= after; ++i) {
    const std::size_t ku = std::min(*done_u + static_cast<std::size_t>(i), set.length(user) - 1);
    last_a = std::min(*done_a + static_cast<std::size_t>(i), set.length(avatar) - 1);
    append_frames(resampled(d, bu + ku, bu + ku, 1), resampled(d, ba + last_a, ba + last_a, 1), 1,
                  pair);
  }
  std::copy_n(set.end_effectors(avatar, *onset_a).begin(), kEndEffectorSize,
              pair.avatar_initial.begin());
  pair.avatar_target = set.hand_target_in_root(avatar, last_a);
  return pair;
}

AlignedPair align_whole(const TestSet& set, std::size_t user, std::size_t avatar) {
  const std::size_t onset_u = first_key(set, user).value_or(0);
  const std::size_t onset_a = first_key(set, avatar).value_or(0);
  const std::vector<std::size_t> bu = phase_bounds(set, user, onset_u);
  const std::vector<std::size_t> ba = phase_bounds(set, avatar, onset_a);
  const dataset::Dataset& d = set.data();
  const std::size_t user_rows = set.length(user) - onset_u;
  const std::size_t u0 = d.begin(user), a0 = d.begin(avatar);
  const Columns u = resampled(d, u0 + onset_u, u0 + set.length(user) - 1, user_rows);
  Columns a;
  if (bu.size() == ba.size()) {
    // Phase by phase: avatar rows [ba_k, ba_k+1] onto the user's [bu_k, bu_k+1] (shared ends).
    for (std::size_t k = 0; k + 1 < bu.size(); ++k) {
      const bool last = k + 2 == bu.size();
      const std::size_t count = bu[k + 1] - bu[k] + (last ? 1 : 0);
      const Columns part = resampled(d, a0 + ba[k], a0 + ba[k + 1], bu[k + 1] - bu[k] + 1);
      a.target.insert(
          a.target.end(), part.target.begin(),
          part.target.begin() + static_cast<std::ptrdiff_t>(count * kTargetFeatureSize));
    }
    if (bu.size() == 1) {
      a = resampled(d, a0 + onset_a, a0 + set.length(avatar) - 1, user_rows);
    }
  } else {
    a = resampled(d, a0 + onset_a, a0 + set.length(avatar) - 1, user_rows);
  }
  AlignedPair pair;
  append_frames(u, a, user_rows, pair);
  std::copy_n(set.end_effectors(avatar, onset_a).begin(), kEndEffectorSize,
              pair.avatar_initial.begin());
  pair.avatar_target = set.hand_target_in_root(avatar, set.length(avatar) - 1);
  pair.completion = user_rows - 1;
  return pair;
}

}  // namespace deixis::eval
