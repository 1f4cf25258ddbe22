#include "train/parallel_steps.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "train/schedule.h"

namespace deixis::train {

namespace {

constexpr int kWindowRows = MoeStep::kWindowRows;

int ceil_div(int a, int b) {
  return (a + b - 1) / b;
}

using Clock = std::chrono::steady_clock;
double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// The same tensors at the same offsets in member m's gradient buffer.
AutoencoderBuffers member_buffers(GradientTeam& team, int member, const AutoencoderBuffers& flat) {
  AutoencoderBuffers b;
  for (int i = 0; i < 4; ++i) {
    b.weight[i] = team.member_pointer(member, flat.weight[i]);
    b.bias[i] = team.member_pointer(member, flat.bias[i]);
  }
  return b;
}

}  // namespace

GradientTeam::GradientTeam(int members, std::span<float> flat_gradients)
    : team_(std::make_unique<StepTeam>(members)),
      flat_gradients_(flat_gradients),
      losses_(static_cast<std::size_t>(members), 0.0) {
  for (int m = 1; m < members; ++m) {
    member_gradients_.emplace_back(flat_gradients.size(), 0.0f);
  }
}

float* GradientTeam::member_pointer(int member, float* flat_pointer) {
  const std::ptrdiff_t offset = flat_pointer - flat_gradients_.data();
  if (offset < 0 || static_cast<std::size_t>(offset) >= flat_gradients_.size()) {
    throw Error("GradientTeam: a gradient outside the flat gradient buffer");
  }
  if (member == 0) {
    return flat_pointer;
  }
  return member_gradients_[static_cast<std::size_t>(member - 1)].data() + offset;
}

void GradientTeam::clear_member(int member) {
  if (member > 0) {
    AlignedFloats& g = member_gradients_[static_cast<std::size_t>(member - 1)];
    std::fill(g.begin(), g.end(), 0.0f);
  }
}

std::pair<int, int> GradientTeam::slice(int member, int count) const {
  const int share = ceil_div(count, members());
  return {std::min(count, member * share), std::min(count, (member + 1) * share)};
}

double GradientTeam::run_slices(int count, bool backward,
                                const std::function<double(int, int, int)>& forward,
                                const std::function<void(int)>& backward_pass) {
  const Clock::time_point start = Clock::now();
  team_->run([&](int m) {
    const auto [first, last] = slice(m, count);
    double& loss = losses_[static_cast<std::size_t>(m)];
    loss = 0;
    if (last <= first) {  // a small batch: nothing for this member
      if (backward) {
        clear_member(m);
      }
      return;
    }
    const Clock::time_point t0 = Clock::now();
    loss = forward(m, first, last);
    const Clock::time_point t1 = Clock::now();
    if (backward) {
      backward_pass(m);
    }
    if (m == 0) {
      forward_seconds_ = seconds_between(t0, t1);
      backward_seconds_ = seconds_between(t1, Clock::now());
    }
  });
  // The team's wall time, shared between forward and backward as member 0 spent its own.
  const double wall = seconds_between(start, Clock::now());
  const double member = forward_seconds_ + backward_seconds_;
  if (member > 0) {
    forward_seconds_ = wall * forward_seconds_ / member;
    backward_seconds_ = wall - forward_seconds_;
  }
  double total = 0;
  for (const double l : losses_) {
    total += l;
  }
  return total;
}

void adamw_on_team(StepTeam& team, const AdamWBuffers& flat, const Schedule& schedule, double lr,
                   std::int64_t step, const std::vector<AlignedFloats>& extra) {
  const std::size_t n = flat.values.size();
  // Ranges of whole cache lines, one per member.
  const std::size_t share = (n / static_cast<std::size_t>(team.size()) + 1 + 15) / 16 * 16;
  team.run([&](int member) {
    const std::size_t first = std::min(n, static_cast<std::size_t>(member) * share);
    const std::size_t count = std::min(n, first + share) - first;
    if (count == 0) {
      return;
    }
    float* sum = flat.grads.data() + first;
    for (const AlignedFloats& other : extra) {
      const float* add = other.data() + first;
      for (std::size_t i = 0; i < count; ++i) {
        sum[i] += add[i];
      }
    }
    adamw_step({flat.values.subspan(first, count), flat.grads.subspan(first, count),
                flat.exp_avg.subspan(first, count), flat.exp_avg_sq.subspan(first, count)},
               schedule, lr, step);
  });
}

ParallelMoeStep::ParallelMoeStep(const MoeShape& shape, int batch_size, int members,
                                 const MoeBuffers& parameters, const MoeBuffers& gradients)
    : team_(std::make_unique<StepTeam>(members)),
      sync_(members),
      batch_size_(batch_size),
      step_(shape, batch_size, members),
      parameters_(parameters),
      gradients_(gradients) {}

double ParallelMoeStep::window(float* clips, int columns, int window, int count, bool feed_back,
                               bool backward) {
  const MoeShape& shape = step_.shape();
  const auto item_stride = static_cast<std::size_t>(kClipRows) * static_cast<std::size_t>(columns);
  const auto row = static_cast<std::size_t>(columns);
  float* newest = clips + static_cast<std::size_t>(kWindowRows - 1 + window) * row;
  // Checked here, before the team starts: a member that threw between two meetings would leave
  // the others waiting at the barrier for ever.
  if (count < 1 || count > batch_size_) {
    throw Error("ParallelMoeStep: " + std::to_string(count) + " clips, the step holds 1 to " +
                std::to_string(batch_size_));
  }
  if (feed_back) {
    const std::span<const float> previous = step_.prediction();
    if (previous.size() != static_cast<std::size_t>(count * shape.pose_columns) ||
        shape.pose_columns != shape.expert_out) {
      throw Error("ParallelMoeStep: no prediction of the previous window to feed back for " +
                  std::to_string(count) + " clips");
    }
    for (int i = 0; i < count; ++i) {
      std::copy_n(previous.data() + static_cast<std::size_t>(i * shape.pose_columns),
                  shape.pose_columns, newest + static_cast<std::size_t>(i) * item_stride);
    }
  }
  const WindowBatch windows{clips + static_cast<std::size_t>(window) * row, item_stride, row};
  const TargetBatch targets{newest + static_cast<std::size_t>(shape.window_columns), item_stride};
  const Clock::time_point start = Clock::now();
  Clock::time_point forward_end;
  double loss = 0;
  team_->run([&](int m) {
    const ExpertTeam member{m, team_->size(), &sync_};
    auto work = [&] {
      const double l = step_.forward(parameters_, windows, targets, count, member);
      if (m == 0) {
        loss = l;
        forward_end = Clock::now();
      }
      if (backward) {
        step_.backward(parameters_, gradients_, member);
      }
    };
    if (member.members == 1) {
      work();
      return;
    }
    // Between meetings nothing may leave a member early: the others would wait for it at the
    // barrier for ever. (The arguments were checked above; what remains is running out of
    // memory.) An end with a message beats a hang.
    try {
      work();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "deixis-train: training thread %d failed inside a step: %s\n", m,
                   e.what());
      std::abort();
    }
  });
  forward_seconds_ = seconds_between(start, forward_end);
  backward_seconds_ = seconds_between(forward_end, Clock::now());
  return loss;
}

ParallelAutoencoderStep::ParallelAutoencoderStep(int batch_size, int members,
                                                 const AutoencoderBuffers& parameters,
                                                 const AutoencoderBuffers& gradients,
                                                 std::span<float> flat_gradients)
    : GradientTeam(members, flat_gradients), parameters_(parameters) {
  if (batch_size < members) {
    throw Error("--threads " + std::to_string(members) + " needs batches of at least " +
                std::to_string(members) + " segments, not " + std::to_string(batch_size));
  }
  for (int m = 0; m < members; ++m) {
    steps_.emplace_back(ceil_div(batch_size, members));
    gradients_.push_back(member_buffers(*this, m, gradients));
  }
}

double ParallelAutoencoderStep::batch(const float* segments, int count, bool backward) {
  const std::size_t segment =
      static_cast<std::size_t>(AutoencoderStep::kFrames) * AutoencoderStep::kChannels;
  auto forward = [&](int m, int first, int last) {
    return steps_[static_cast<std::size_t>(m)].forward(
        parameters_, segments + static_cast<std::size_t>(first) * segment, last - first, count);
  };
  auto backward_pass = [&](int m) {
    steps_[static_cast<std::size_t>(m)].backward(parameters_,
                                                 gradients_[static_cast<std::size_t>(m)]);
  };
  return run_slices(count, backward, forward, backward_pass);
}

}  // namespace deixis::train
