// The conditions matrix: loss 0 / 5 / 20 % × {clean, delay + jitter, reordering + duplicates},
// open and sealed, each a seeded 20 s stream at 30 Hz through the simulated network between two
// in-process sessions. In every row the receiver plays frames in order, each sequence number once
// (as a frame or as missed tracking), never a duplicate, never a stopped stream; missed tracking
// stays near the loss rate; frames are the sender's within quantisation; added delay stays near
// the configured 50 ms. The rows are printed as a table (docs/protocol.md quotes it).

#include <gtest/gtest.h>

#include <cstdio>

#include "session_pair.h"

namespace deixis::net {
namespace {

struct Profile {
  const char* name;
  double delay, jitter, reorder, reorder_delay, duplicate;
};

constexpr Profile kProfiles[] = {
    {"clean 20 ms", 0.020, 0.0, 0.0, 0.0, 0.0},
    {"40 ms ± 10 ms", 0.040, 0.010, 0.0, 0.0, 0.0},
    {"30 ms ± 5, reorder, dup", 0.030, 0.005, 0.10, 0.030, 0.10},
};
constexpr double kLosses[] = {0.0, 0.05, 0.20};
constexpr double kSeconds = 20.0;

struct Row {
  std::uint32_t sent = 0;
  std::uint64_t played = 0, missed = 0, longest_gap = 0;
  std::uint64_t trailing = 0;  // missed after the sender stopped: held until the stream stops
  double worst_latency = 0.0;  // sender tick to playout (s)
};

class Conditions : public ::testing::TestWithParam<std::tuple<int, int, bool>> {};

TEST_P(Conditions, InOrderNoDuplicatesBoundedMissedTracking) {
  const auto [profile_index, loss_index, sealed] = GetParam();
  const Profile& profile = kProfiles[profile_index];
  const double loss = kLosses[loss_index];
  LinkConditions c;
  c.loss = loss;
  c.delay = profile.delay;
  c.jitter = profile.jitter;
  c.reorder = profile.reorder;
  c.reorder_delay = profile.reorder_delay;
  c.duplicate = profile.duplicate;
  const std::string passphrase = sealed ? "matrix" : "";
  testing::SessionPair pair(c, 1000 + 10 * profile_index + loss_index, passphrase, passphrase);
  ASSERT_TRUE(pair.connect(10.0)) << "connects despite the conditions";

  const Vec3 root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  Row row;
  std::int64_t last_sequence = -1;
  std::uint64_t gap = 0;
  double next_tick = pair.now;
  const double start = pair.now;
  const double end = pair.now + kSeconds;
  while (pair.now < end + 1.0) {
    if (pair.now >= next_tick && pair.now < end) {
      TrackingFrame f = testing::moving_frame(row.sent, root);
      f.time = start + row.sent * testing::kTick;  // the sender's clock: the shared one here
      pair.joiner.send_tracking(f);
      ++row.sent;
      next_tick += testing::kTick;
    }
    pair.step(0.002);
    for (Playout p = pair.host.next_frame(pair.now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
         p = pair.host.next_frame(pair.now)) {
      if (last_sequence < 0) {
        ASSERT_LE(p.sequence, 3u) << "starts with the first frame that arrived";
      } else {
        ASSERT_EQ(static_cast<std::int64_t>(p.sequence), last_sequence + 1)
            << "every sequence number once, in order";
      }
      last_sequence = p.sequence;
      if (p.sequence >= row.sent && pair.now > end) {
        ASSERT_EQ(p.kind, PlayoutKind::kMissed);
        ++row.trailing;
        continue;
      }
      if (p.kind == PlayoutKind::kMissed) {
        ++row.missed;
        row.longest_gap = std::max(row.longest_gap, ++gap);
        continue;
      }
      gap = 0;
      ++row.played;
      const TrackingFrame sent = testing::moving_frame(p.sequence, root);
      ASSERT_LT((p.frame->T_world_head.translation - sent.T_world_head.translation).norm(), 0.001f);
      ASSERT_EQ(p.frame->head_target, sent.head_target);
      row.worst_latency =
          std::max(row.worst_latency, pair.now - (start + p.sequence * testing::kTick));
    }
  }
  const JitterStats& j = pair.host.jitter();
  const DropCounters& drops = pair.host.drops();
  std::printf(
      "| %-24s | %4.0f %% | %-6s | %4u | %4llu | %3llu | %3llu | %3llu | %3llu | %4.1f | %5.1f |\n",
      profile.name, 100.0 * loss, sealed ? "sealed" : "open", row.sent,
      static_cast<unsigned long long>(row.played), static_cast<unsigned long long>(row.missed),
      static_cast<unsigned long long>(row.longest_gap), static_cast<unsigned long long>(j.late),
      static_cast<unsigned long long>(j.duplicates + drops[DropReason::kReplayed]),
      1000.0 * j.waited_sum / static_cast<double>(std::max<std::uint64_t>(1, j.played)),
      1000.0 * row.worst_latency);

  EXPECT_TRUE(pair.both_streaming()) << "no time-out under these conditions";
  // Only the end of the stream is reported as a stop, once, after a bounded hold.
  EXPECT_EQ(j.stops, 1u) << "the stream never looked stopped before its end";
  EXPECT_LE(row.trailing, 15u) << "(stop_after − delay) / frame period";
  EXPECT_EQ(pair.host.next_frame(pair.now).kind, PlayoutKind::kNoStream) << "hidden at the end";
  EXPECT_EQ(j.restarts, 0u);
  // Every frame sent came out once, as a frame or as missed tracking (the last few may still be
  // in flight when the sender stops, and the first may be lost before the stream starts).
  EXPECT_GE(row.played + row.missed + 3, row.sent);
  EXPECT_LE(row.played + row.missed, row.sent);
  // Missed tracking is the loss, plus frames later than the delay: bounded.
  const double n = row.sent;
  EXPECT_LE(static_cast<double>(row.missed), 1.4 * loss * n + 0.02 * n + 3.0);
  if (loss == 0.0 && profile.jitter == 0.0) {
    EXPECT_EQ(row.missed, 0u);
  }
  if (loss > 0.0) {
    EXPECT_GE(static_cast<double>(row.missed), 0.6 * loss * n) << "losses do show as missed";
  }
  EXPECT_LE(row.longest_gap, 8u);
  if (profile.duplicate > 0.0) {
    EXPECT_GT(j.duplicates + drops[DropReason::kReplayed], 0u) << "duplicates arrived";
    EXPECT_GT(pair.network.stats().reordered, 0u);
  }
  // Sender tick to playout: the transit, plus the 50 ms delay, plus the wait for jitter.
  EXPECT_LE(row.worst_latency, profile.delay + 3.5 * profile.jitter + profile.reorder_delay +
                                   pair.host.config().jitter.delay + 0.01);
  EXPECT_EQ(drops.total, drops[DropReason::kReplayed]) << "nothing else was dropped";
}

INSTANTIATE_TEST_SUITE_P(Matrix, Conditions,
                         ::testing::Combine(::testing::Range(0, 3), ::testing::Range(0, 3),
                                            ::testing::Bool()));

}  // namespace
}  // namespace deixis::net
