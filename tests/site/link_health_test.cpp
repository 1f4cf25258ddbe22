// What the presence panels say about a remote person's link (site/link_health.h): the window's
// arithmetic on known counters (frames due and dropped over the last 5 s, the mean wait in the
// jitter buffer, a loss burst clearing once it is older than the window), the line's words, and
// the figures of a real session under known conditions (the simulated network's loss and delay,
// tests/net/session_pair.h): dropped / due near the loss, the buffer's delay near its
// configured 50 ms, the round trip twice the one-way delay.

#include "site/link_health.h"

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "net/session_pair.h"

namespace deixis::site {
namespace {

constexpr double kTick = 1.0 / 30.0;

// A stream at 30 Hz whose frames each waited `wait` s; every `miss_every`-th one missed (0:
// none) while `missing` says so.
struct Stream {
  net::JitterStats stats;
  std::uint64_t tick = 0;
  void advance(bool missed, double wait = 0.05) {
    if (missed) {
      ++stats.missed;
    } else {
      ++stats.played;
      stats.waited_sum += wait;
    }
    ++tick;
  }
  double now() const { return static_cast<double>(tick) * kTick; }
};

TEST(LinkWindow, CountsTheLastFiveSecondsOfDueAndDroppedFrames) {
  LinkWindow window;
  EXPECT_EQ(window.figures().due, 0u);
  EXPECT_LT(window.figures().buffer_delay_ms, 0.0) << "nothing played yet";
  Stream s;
  for (int i = 0; i < 300; ++i) {  // 10 s, one frame in ten missed
    s.advance(i % 10 == 9);
    window.update(s.now(), s.stats);
  }
  const LinkFigures f = window.figures();
  EXPECT_NEAR(f.window_s, LinkWindow::kWindow, LinkWindow::kInterval);
  // 30 frames per second over the window's length, a tenth of them dropped.
  EXPECT_NEAR(static_cast<double>(f.due), 30.0 * f.window_s, 1.0);
  EXPECT_NEAR(static_cast<double>(f.dropped), 3.0 * f.window_s, 1.0);
  EXPECT_NEAR(f.buffer_delay_ms, 50.0, 1e-6);
}

TEST(LinkWindow, ALossBurstShowsForAWindowAndThenClears) {
  LinkWindow window;
  Stream s;
  const auto run = [&](int ticks, bool missed) {
    for (int i = 0; i < ticks; ++i) {
      s.advance(missed, 0.08);
      window.update(s.now(), s.stats);
    }
  };
  run(150, false);
  run(30, true);  // a second with nothing coming
  EXPECT_EQ(window.figures().dropped, 30u);
  run(60, false);
  EXPECT_EQ(window.figures().dropped, 30u) << "2 s later it is still within the window";
  EXPECT_NEAR(window.figures().buffer_delay_ms, 80.0, 1e-6);
  run(120, false);
  EXPECT_EQ(window.figures().dropped, 0u) << "6 s later it has left the window";
  window.reset();
  EXPECT_EQ(window.figures().due, 0u);
  EXPECT_EQ(window.figures().window_s, 0.0);
}

TEST(LinkLine, SaysStateRoundTripBufferAndDrops) {
  LinkFigures f;
  f.state = LinkState::kLive;
  f.round_trip_ms = 42;
  f.buffer_delay_ms = 51.2;
  f.due = 150;
  f.dropped = 3;
  f.window_s = 5.0;
  std::array<char, 128> out{};
  std::size_t n = format_link_line("B", f, out);
  EXPECT_EQ(std::string(out.data(), n),
            "B: live, rtt 42 ms, buffer 51 ms, dropped 3 of 150 in 5 s");
  f.via_relay = true;
  f.state = LinkState::kStalled;
  n = format_link_line("C", f, out);
  EXPECT_EQ(std::string(out.data(), n),
            "C: stalled, rtt 42 ms to relay, buffer 51 ms, dropped 3 of 150 in 5 s");
  // Nothing known yet.
  n = format_link_line("D", LinkFigures{}, out);
  EXPECT_EQ(std::string(out.data(), n), "D: waiting, rtt ?, buffer -, dropped 0 of 0 in 0 s");
  // Too small a buffer: cut, terminated, the length what was kept.
  std::array<char, 10> small{};
  n = format_link_line("B", f, small);
  EXPECT_EQ(n, 9u);
  EXPECT_EQ(std::string(small.data()), "B: stalle");
}

// The conditions shim: a joiner streams to a host through the simulated network with 15 % loss
// and 60 ms each way; the host's window over its jitter buffer says what the network did.
TEST(LinkWindow, ASessionUnderKnownLossAndDelayReadsThem) {
  net::LinkConditions c;
  c.loss = 0.15;
  c.delay = 0.060;
  testing::SessionPair pair(c, 77);
  ASSERT_TRUE(pair.connect(10.0));
  const Vec3 root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  LinkWindow window;
  std::uint32_t sent = 0;
  double next_tick = pair.now;
  const double end = pair.now + 12.0;
  while (pair.now < end) {
    if (pair.now >= next_tick) {
      TrackingFrame f = testing::moving_frame(sent++, root);
      f.time = pair.now;
      pair.joiner.send_tracking(f);
      next_tick += kTick;
    }
    pair.step(0.002);
    for (net::Playout p = pair.host.next_frame(pair.now);
         p.kind == net::PlayoutKind::kFrame || p.kind == net::PlayoutKind::kMissed;
         p = pair.host.next_frame(pair.now)) {
    }
    window.update(pair.now, pair.host.jitter());
  }
  const LinkFigures f = window.figures();
  EXPECT_NEAR(f.window_s, LinkWindow::kWindow, LinkWindow::kInterval);
  EXPECT_NEAR(static_cast<double>(f.due), 30.0 * f.window_s, 3.0);
  // 150 frames at 15 %: 22.5 expected, 4.4 standard deviation; ±3 of them.
  EXPECT_GE(f.dropped, 9u);
  EXPECT_LE(f.dropped, 36u);
  // Frames wait the configured delay behind the least-delayed ones: without jitter, about it.
  EXPECT_NEAR(f.buffer_delay_ms, 1000.0 * net::JitterConfig{}.delay, 10.0);
  EXPECT_EQ(pair.host.status().round_trip_ms, 120u) << "the link's estimate: twice 60 ms";
  std::printf("15 %% loss, 60 ms each way: %llu of %llu dropped in %.1f s, buffer %.1f ms\n",
              static_cast<unsigned long long>(f.dropped), static_cast<unsigned long long>(f.due),
              f.window_s, f.buffer_delay_ms);
}

}  // namespace
}  // namespace deixis::site
