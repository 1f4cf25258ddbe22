// The jitter buffer on an injected clock: delay, ordering, duplicates, late frames, gaps as
// missed tracking, a stopped stream as kNoStream, restarts.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "net/jitter_buffer.h"

namespace deixis::net {
namespace {

constexpr double kP = 1.0 / 30.0;

// Frame `seq`, stamped on the sender's clock (not ours: it runs `sender_offset` ahead), marked so
// that the test can tell which frame came out.
TrackingFrame frame_at(std::uint32_t seq, double sender_offset = 100.0) {
  TrackingFrame f;
  f.time = sender_offset + seq * kP;
  f.head_target = static_cast<TargetId>(seq);
  return f;
}

TrackingFrame frame_at_time(std::uint32_t seq, double sender_time) {
  TrackingFrame f;
  f.time = sender_time;
  f.head_target = static_cast<TargetId>(seq);
  return f;
}

struct Result {
  PlayoutKind kind;
  std::uint32_t sequence;
  double at;
};

// After the last frame, each period brings one more kMissed (the stream has paused: hold the last
// frame) until stop_after. Checks that everything from `n` on is such, and cuts it off.
void expect_only_missed_after(std::vector<Result>& out, std::size_t n) {
  ASSERT_GE(out.size(), n);
  for (std::size_t i = n; i < out.size(); ++i) {
    EXPECT_EQ(out[i].kind, PlayoutKind::kMissed) << i;
    EXPECT_EQ(out[i].sequence, out[i - 1].sequence + 1);
  }
  out.resize(n);
}

// Pops until pending, collecting everything that came out.
void drain(JitterBuffer& buffer, double now, std::vector<Result>& out) {
  for (Playout p = buffer.pop(now); p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
       p = buffer.pop(now)) {
    if (p.kind == PlayoutKind::kFrame) {
      EXPECT_EQ(p.frame->head_target, static_cast<TargetId>(p.sequence)) << "the right frame";
    }
    out.push_back({p.kind, p.sequence, now});
  }
}

TEST(JitterBuffer, NothingBeforeTheFirstFrame) {
  JitterBuffer buffer;
  EXPECT_EQ(buffer.pop(0.0).kind, PlayoutKind::kNoStream);
  EXPECT_FALSE(buffer.streaming());
}

TEST(JitterBuffer, PlaysFramesTheConfiguredDelayBehind) {
  JitterConfig config;
  config.delay = 0.050;
  JitterBuffer buffer(config);
  const double transit = 0.020;
  buffer.push(0, frame_at(0), 0.0 + transit);
  EXPECT_EQ(buffer.pop(transit).kind, PlayoutKind::kPending);
  EXPECT_EQ(buffer.pop(transit + 0.049).kind, PlayoutKind::kPending);
  const Playout p = buffer.pop(transit + 0.050);
  ASSERT_EQ(p.kind, PlayoutKind::kFrame);
  EXPECT_EQ(p.sequence, 0u);
  EXPECT_NEAR(p.waited, 0.050, 1e-9);
  EXPECT_EQ(buffer.pop(transit + 0.050).kind, PlayoutKind::kPending) << "one frame, once";
}

TEST(JitterBuffer, ReordersBySequenceAndDropsDuplicates) {
  JitterBuffer buffer;
  // Frames 0..5 sent every tick; 2 and 3 swap places, 4 arrives twice.
  const std::vector<std::pair<std::uint32_t, double>> arrivals = {
      {0, 0.010}, {1, 0.043}, {3, 0.110}, {2, 0.112}, {4, 0.143}, {4, 0.150}, {5, 0.177}};
  std::vector<Result> out;
  std::size_t next = 0;
  for (double now = 0.0; now < 0.5; now += 0.001) {
    while (next < arrivals.size() && arrivals[next].second <= now) {
      buffer.push(arrivals[next].first, frame_at(arrivals[next].first), arrivals[next].second);
      ++next;
    }
    drain(buffer, now, out);
  }
  expect_only_missed_after(out, 6);
  for (std::uint32_t i = 0; i < 6; ++i) {
    EXPECT_EQ(out[i].kind, PlayoutKind::kFrame);
    EXPECT_EQ(out[i].sequence, i);
    if (i > 0) {
      EXPECT_NEAR(out[i].at - out[i - 1].at, kP, 0.0011) << "evenly spaced";
    }
  }
  EXPECT_EQ(buffer.stats().duplicates, 1u);
}

TEST(JitterBuffer, AGapIsMissedTrackingAtItsTurnAndALateFrameIsDropped) {
  JitterBuffer buffer;
  std::vector<Result> out;
  // Frame 2 is lost in transit and arrives 0.3 s late; everything else takes 10 ms.
  for (double now = 0.0; now < 0.6; now += 0.001) {
    for (std::uint32_t s = 0; s < 10; ++s) {
      const double arrival = s * kP + (s == 2 ? 0.3 : 0.010);
      if (arrival <= now && arrival > now - 0.001) {
        buffer.push(s, frame_at(s), arrival);
      }
    }
    drain(buffer, now, out);
  }
  const std::uint64_t missed_at_the_end = out.size() - 10;
  expect_only_missed_after(out, 10);
  for (std::uint32_t s = 0; s < 10; ++s) {
    EXPECT_EQ(out[s].sequence, s);
    EXPECT_EQ(out[s].kind, s == 2 ? PlayoutKind::kMissed : PlayoutKind::kFrame) << s;
  }
  // The missed frame is reported when it was due, one period after frame 1.
  EXPECT_NEAR(out[2].at - out[1].at, kP, 0.0011);
  EXPECT_EQ(buffer.stats().missed, 1u + missed_at_the_end);
  EXPECT_EQ(buffer.stats().late, 1u);
  EXPECT_EQ(buffer.stats().played, 9u);
}

TEST(JitterBuffer, JitterWithinTheDelayCostsNothing) {
  JitterConfig config;
  config.delay = 0.050;
  JitterBuffer buffer(config);
  std::vector<Result> out;
  // Transit alternates between 5 ms and 50 ms: 45 ms of jitter, under the 50 ms delay.
  std::vector<std::pair<double, std::uint32_t>> arrivals;
  for (std::uint32_t s = 0; s < 60; ++s) {
    arrivals.push_back({s * kP + (s % 2 == 0 ? 0.005 : 0.050), s});
  }
  std::sort(arrivals.begin(), arrivals.end());
  std::size_t next = 0;
  for (double now = 0.0; now < 2.5; now += 0.001) {
    while (next < arrivals.size() && arrivals[next].first <= now) {
      buffer.push(arrivals[next].second, frame_at(arrivals[next].second), arrivals[next].first);
      ++next;
    }
    drain(buffer, now, out);
  }
  expect_only_missed_after(out, 60);
  EXPECT_EQ(buffer.stats().late, 0u);
  // Played at sender time + 5 ms + 50 ms, whatever the transit.
  for (const Result& r : out) {
    EXPECT_EQ(r.kind, PlayoutKind::kFrame);
    EXPECT_NEAR(r.at, r.sequence * kP + 0.055, 0.0011);
  }
}

TEST(JitterBuffer, AStoppedStreamIsReportedSoTheAvatarIsHidden) {
  JitterConfig config;
  config.stop_after = 0.5;
  JitterBuffer buffer(config);
  std::vector<Result> out;
  double now = 0.0;
  for (; now < 3.0; now += 0.001) {
    const auto s = static_cast<std::uint32_t>(std::floor(now / kP));
    if (now < 1.0 && std::abs(now - (s * kP + 0.01)) < 0.0005) {
      buffer.push(s, frame_at(s), now);  // the stream stops after 1 s
    }
    const Playout p = buffer.pop(now);
    if (p.kind == PlayoutKind::kNoStream && now > 1.0) {
      break;
    }
    if (p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed) {
      out.push_back({p.kind, p.sequence, now});
    }
  }
  // Stopped 0.5 s after the last arrival; until then, missed tracking (hold the last frame).
  EXPECT_NEAR(now, 29 * kP + 0.01 + 0.5, 0.002);
  EXPECT_EQ(buffer.stats().stops, 1u);
  std::uint64_t missed = 0;
  for (const Result& r : out) {
    missed += r.kind == PlayoutKind::kMissed ? 1 : 0;
  }
  EXPECT_EQ(missed, buffer.stats().missed);
  EXPECT_GE(missed, 12u);  // (0.5 s − 50 ms delay) / 33 ms
  EXPECT_LE(missed, 14u);
  EXPECT_EQ(buffer.pop(now + 1.0).kind, PlayoutKind::kNoStream) << "stays hidden";
  EXPECT_FALSE(buffer.streaming());
  // It comes back when frames do.
  buffer.push(200, frame_at(200), now + 1.0);
  EXPECT_TRUE(buffer.streaming());
  EXPECT_EQ(buffer.pop(now + 1.2).kind, PlayoutKind::kFrame);
}

TEST(JitterBuffer, StartsWithTheLowestSequenceEvenIfItArrivesSecond) {
  JitterBuffer buffer;
  buffer.push(1, frame_at(1), 0.040);
  buffer.push(0, frame_at(0), 0.045);  // overtaken, but inside the delay
  std::vector<Result> out;
  for (double now = 0.04; now < 0.3; now += 0.001) {
    drain(buffer, now, out);
  }
  expect_only_missed_after(out, 2);
  EXPECT_EQ(out[0].kind, PlayoutKind::kFrame);
  EXPECT_EQ(out[1].kind, PlayoutKind::kFrame);
  EXPECT_EQ(out[0].sequence, 0u);
  EXPECT_EQ(out[1].sequence, 1u);
}

TEST(JitterBuffer, ASenderClockJumpOrASequenceFarAheadRestartsTheSchedule) {
  JitterBuffer buffer;
  std::vector<Result> out;
  buffer.push(0, frame_at(0), 0.01);
  drain(buffer, 0.065, out);  // due at 0.06
  ASSERT_EQ(out.size(), 1u);
  // The sender's clock jumps by an hour (a wrap, a restart): played on a fresh schedule.
  buffer.push(1, frame_at(1, 3700.0), 0.07);
  EXPECT_EQ(buffer.stats().restarts, 1u);
  drain(buffer, 0.125, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].kind, PlayoutKind::kFrame);
  EXPECT_EQ(out[1].sequence, 1u);
  // A sequence number far ahead: the same.
  buffer.push(1000, frame_at(1000, 3700.0), 0.13);
  EXPECT_EQ(buffer.stats().restarts, 2u);
  drain(buffer, 0.185, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[2].kind, PlayoutKind::kFrame);
  EXPECT_EQ(out[2].sequence, 1000u);
  EXPECT_EQ(buffer.stats().missed, 0u) << "a restart is not 998 missed frames";
}

// Drives the buffer with frames 0..n−1 sent every tick (sender clock `sender_time(s)`) arriving
// after `transit(s)`, popping every millisecond; returns what came out.
std::vector<Result> run_stream(JitterBuffer& buffer, std::uint32_t n,
                               const std::function<double(std::uint32_t)>& sender_time,
                               const std::function<double(std::uint32_t)>& transit) {
  std::vector<std::pair<double, std::uint32_t>> arrivals;
  for (std::uint32_t s = 0; s < n; ++s) {
    arrivals.push_back({s * kP + transit(s), s});
  }
  std::sort(arrivals.begin(), arrivals.end());
  std::vector<Result> out;
  std::size_t next = 0;
  for (double now = 0.0; next < arrivals.size() || now < arrivals.back().first + 0.2;
       now += 0.001) {
    while (next < arrivals.size() && arrivals[next].first <= now) {
      const std::uint32_t s = arrivals[next].second;
      buffer.push(s, frame_at_time(s, sender_time(s)), arrivals[next].first);
      ++next;
    }
    drain(buffer, now, out);
  }
  return out;
}

TEST(JitterBuffer, TwoFreakEarlyArrivalsDoNotPullTheScheduleForward) {
  JitterBuffer buffer;
  // 20 ms transit, except two frames that take 1 ms: a minimum-based schedule would move 19 ms
  // earlier and the usual frames would still be fine, but by less; here the schedule stays put.
  const auto transit = [](std::uint32_t s) { return s == 40 || s == 45 ? 0.001 : 0.020; };
  std::vector<Result> out = run_stream(
      buffer, 90, [](std::uint32_t s) { return 50.0 + s * kP; }, transit);
  expect_only_missed_after(out, 90);
  for (const Result& r : out) {
    EXPECT_EQ(r.kind, PlayoutKind::kFrame);
    if (r.sequence > 50) {
      EXPECT_NEAR(r.at, r.sequence * kP + 0.020 + 0.050, 0.0011) << r.sequence;
    }
  }
}

TEST(JitterBuffer, ASenderClockStepBackIsFollowedAfterAFewLateFrames) {
  JitterBuffer buffer;
  // From frame 60 on, the sender's clock reads 200 ms less (an NTP step): its frames look 200 ms
  // late against the old schedule.
  const auto sender_time = [](std::uint32_t s) { return 50.0 + s * kP - (s >= 60 ? 0.2 : 0.0); };
  std::vector<Result> out =
      run_stream(buffer, 150, sender_time, [](std::uint32_t) { return 0.010; });
  // The schedule ran 200 ms ahead of the frames: a few came too late (missed tracking, held),
  // then the offset started again and every later frame played, in order.
  EXPECT_EQ(buffer.stats().offset_resets, 1u);
  EXPECT_GE(buffer.stats().late, static_cast<std::uint64_t>(JitterBuffer::kLateStreak));
  EXPECT_LE(buffer.stats().late, static_cast<std::uint64_t>(JitterBuffer::kLateStreak) + 5);
  EXPECT_EQ(buffer.stats().restarts, 0u) << "followed, not restarted";
  std::int64_t last = -1;
  for (const Result& r : out) {
    EXPECT_EQ(static_cast<std::int64_t>(r.sequence), last + 1);
    last = r.sequence;
    if (r.sequence < 60 || (r.sequence >= 70 && r.sequence < 150)) {
      EXPECT_EQ(r.kind, PlayoutKind::kFrame) << r.sequence;
    }
  }
}

TEST(JitterBuffer, SequenceNumbersWrap) {
  JitterBuffer buffer;
  std::vector<Result> out;
  const std::uint32_t first = 0xFFFFFFFEu;
  for (std::uint32_t i = 0; i < 5; ++i) {
    buffer.push(first + i, frame_at_time(first + i, 100.0 + i * kP), i * kP + 0.01);
    drain(buffer, i * kP + 0.01, out);
  }
  drain(buffer, 0.3, out);
  expect_only_missed_after(out, 5);
  for (std::uint32_t i = 0; i < 5; ++i) {
    EXPECT_EQ(out[i].sequence, first + i);
    EXPECT_EQ(out[i].kind, PlayoutKind::kFrame);
  }
}

TEST(JitterBuffer, ResetForgetsTheStreamButKeepsTheCounts) {
  JitterBuffer buffer;
  buffer.push(0, frame_at(0), 0.0);
  buffer.push(0, frame_at(0), 0.0);
  buffer.reset();
  EXPECT_EQ(buffer.pop(0.1).kind, PlayoutKind::kNoStream);
  EXPECT_EQ(buffer.stats().received, 2u);
  EXPECT_EQ(buffer.stats().duplicates, 1u);
}

// ---- Sequence numbers from the network, however far off (serial-number arithmetic) ----
// Distances are taken from the next frame due. Exactly half the sequence space (2^31) counts as
// behind: dropped as late. Under the ASan/UBSan build the old signed arithmetic failed at 2^31
// (`age = -d` overflowed, then a shift by INT_MAX − 1).

constexpr std::uint32_t kHalfSpace = 0x80000000u;

// A stream on the injected clock: one frame sent per tick with 10 ms of transit, popped every tick.
struct Stream {
  JitterBuffer buffer;
  std::vector<Result> out;
  double now = 0.01;

  // Sends `sequence`, stamped on the sender's clock as sent 10 ms ago (no clock jump).
  void send(std::uint32_t sequence) {
    buffer.push(sequence, frame_at_time(sequence, 100.0 + now - 0.01), now);
  }
  void tick(int n = 1) {
    for (int i = 0; i < n; ++i) {
      now += kP;
      drain(buffer, now, out);
    }
  }
  // Sends first, first + 1, … (n frames), ticking after each.
  void run(std::uint32_t first, std::uint32_t n) {
    for (std::uint32_t i = 0; i < n; ++i) {
      send(first + i);
      tick();
    }
  }
  // The next frame due once something came out.
  std::uint32_t next() const { return out.back().sequence + 1; }
  std::size_t count(std::uint32_t sequence, PlayoutKind kind) const {
    return static_cast<std::size_t>(std::count_if(out.begin(), out.end(), [&](const Result& r) {
      return r.sequence == sequence && r.kind == kind;
    }));
  }
};

// What every run below must show: no sequence number came out twice, each result is after the one
// before in serial order, and the counts match what came out.
void expect_each_once_in_order(const Stream& stream) {
  const std::vector<Result>& out = stream.out;
  std::uint64_t frames = 0;
  std::uint64_t missed = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    frames += out[i].kind == PlayoutKind::kFrame ? 1 : 0;
    missed += out[i].kind == PlayoutKind::kMissed ? 1 : 0;
    if (i > 0) {
      const std::uint32_t step = out[i].sequence - out[i - 1].sequence;
      EXPECT_TRUE(step >= 1 && step < kHalfSpace) << "result " << i << " is not after " << i - 1;
    }
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_NE(out[i].sequence, out[j].sequence) << "results " << j << " and " << i;
    }
  }
  EXPECT_EQ(stream.buffer.stats().played, frames);
  EXPECT_EQ(stream.buffer.stats().missed, missed);
}

TEST(JitterBufferSequenceSpace, HalfTheSpaceAwayIsBehindAndDroppedAsLate) {
  Stream stream;
  stream.run(0, 10);
  const std::uint32_t stray = stream.next() + kHalfSpace;
  stream.send(stray);
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  stream.run(10, 10);
  stream.tick(3);
  expect_each_once_in_order(stream);
  expect_only_missed_after(stream.out, 20);
  for (std::uint32_t s = 0; s < 20; ++s) {
    EXPECT_EQ(stream.out[s].sequence, s);
    EXPECT_EQ(stream.out[s].kind, PlayoutKind::kFrame) << s;
  }
  EXPECT_EQ(stream.count(stray, PlayoutKind::kFrame), 0u);
  EXPECT_EQ(stream.buffer.stats().played, 20u);
  EXPECT_EQ(stream.buffer.stats().received, 21u);
  EXPECT_EQ(stream.buffer.stats().duplicates, 0u);
}

TEST(JitterBufferSequenceSpace, HalfTheSpaceFromTheFirstFrameIsDroppedBeforePlaying) {
  Stream stream;
  stream.send(7);
  stream.send(7 + kHalfSpace);  // before the stream plays (the anchor is the reference)
  stream.send(7 - kHalfSpace);  // the same number
  EXPECT_EQ(stream.buffer.stats().late, 2u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  stream.tick(3);
  ASSERT_FALSE(stream.out.empty());
  EXPECT_EQ(stream.out[0].sequence, 7u);
  EXPECT_EQ(stream.out[0].kind, PlayoutKind::kFrame);
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, JustUnderHalfTheSpaceAheadIsTooFarToBelieve) {
  Stream stream;
  stream.run(0, 10);
  // 2^31 − 1 ahead of the next frame is half the space from the last result: old (late).
  stream.send(stream.next() + (kHalfSpace - 1));
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  const std::uint32_t stray = stream.next() + (kHalfSpace - 2);
  stream.send(stray);
  EXPECT_EQ(stream.buffer.stats().far_ahead, 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u) << "one packet does not move the schedule";
  stream.run(10, 10);
  stream.tick(3);
  expect_each_once_in_order(stream);
  expect_only_missed_after(stream.out, 20);
  EXPECT_EQ(stream.buffer.stats().played, 20u);
  EXPECT_EQ(stream.count(stray, PlayoutKind::kFrame), 0u);
}

TEST(JitterBufferSequenceSpace, ASkipUpToTheLimitRestartsOneBeyondItIsDropped) {
  Stream stream;
  stream.run(0, 10);
  const std::uint32_t beyond = stream.next() + JitterBuffer::kMaxSkip;
  stream.send(beyond);
  EXPECT_EQ(stream.buffer.stats().far_ahead, 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  const std::uint32_t skip = stream.next() + (JitterBuffer::kMaxSkip - 1);
  stream.send(skip);
  EXPECT_EQ(stream.buffer.stats().restarts, 1u);
  stream.tick(3);
  EXPECT_EQ(stream.count(skip, PlayoutKind::kFrame), 1u);
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, ASenderThatReallySkippedThatFarIsFollowedOnceTheStreamStops) {
  Stream stream;
  stream.run(0, 10);
  // From here on the sender's numbers are 2^20 ahead: dropped, so the stream stops, then starts
  // again from them.
  const std::uint32_t far = stream.next() + (1u << 20);
  stream.run(far, 30);
  EXPECT_EQ(stream.buffer.stats().stops, 1u);
  EXPECT_GE(stream.buffer.stats().far_ahead, 10u);
  EXPECT_EQ(stream.count(far + 25, PlayoutKind::kFrame), 1u);
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, JustOverHalfTheSpaceAheadIsBehindAndDroppedAsLate) {
  Stream stream;
  stream.run(0, 10);
  const std::uint32_t stray = stream.next() + (kHalfSpace + 1);  // 2^31 − 1 behind
  stream.send(stray);
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  stream.run(10, 5);
  stream.tick(3);
  expect_each_once_in_order(stream);
  expect_only_missed_after(stream.out, 15);
  EXPECT_EQ(stream.buffer.stats().played, 15u);
  EXPECT_EQ(stream.count(stray, PlayoutKind::kFrame), 0u);
}

TEST(JitterBufferSequenceSpace, TheLargestDistanceIsOneBehind) {
  Stream stream;
  stream.run(0, 10);
  // 2^32 − 1 ahead of the next frame due is the frame that just came out: a duplicate.
  const std::uint32_t just_played = stream.next() + 0xFFFFFFFFu;
  ASSERT_EQ(stream.out.back().kind, PlayoutKind::kFrame);
  stream.send(just_played);
  EXPECT_EQ(stream.buffer.stats().duplicates, 1u);
  EXPECT_EQ(stream.buffer.stats().late, 0u);
  // One that was missed at its turn (10 never arrives) is late when it does.
  stream.run(11, 5);
  ASSERT_EQ(stream.count(10, PlayoutKind::kMissed), 1u);
  stream.send(10);
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  stream.tick(3);
  EXPECT_EQ(stream.count(10, PlayoutKind::kFrame), 0u);
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, WrapsFromTheLargestNumberToZero) {
  Stream stream;
  const std::uint32_t first = 0xFFFFFFF0u;
  // 0xFFFFFFFF is lost, then arrives after its turn; 0 arrives twice.
  for (std::uint32_t i = 0; i < 32; ++i) {
    const std::uint32_t s = first + i;
    if (s != 0xFFFFFFFFu) {
      stream.send(s);
    }
    if (s == 0u) {
      stream.send(0u);
    }
    if (s == 4u) {
      stream.send(0xFFFFFFFFu);
      stream.send(0u);
    }
    stream.tick();
  }
  stream.tick(3);
  expect_each_once_in_order(stream);
  expect_only_missed_after(stream.out, 32);
  for (std::uint32_t i = 0; i < 32; ++i) {
    EXPECT_EQ(stream.out[i].sequence, first + i);
    EXPECT_EQ(stream.out[i].kind,
              first + i == 0xFFFFFFFFu ? PlayoutKind::kMissed : PlayoutKind::kFrame)
        << i;
  }
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  EXPECT_EQ(stream.buffer.stats().duplicates, 2u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
}

TEST(JitterBufferSequenceSpace, BeforePlayingTheWindowReachesBackAcrossTheWrap) {
  Stream stream;
  stream.send(2);
  stream.send(0xFFFFFFFFu);  // 3 before the first frame: accepted, and played first
  stream.send(2u - JitterBuffer::kCapacity / 2 - 1);  // 17 before: too old
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  stream.tick(4);
  ASSERT_GE(stream.out.size(), 4u);
  EXPECT_EQ(stream.out[0].sequence, 0xFFFFFFFFu);
  EXPECT_EQ(stream.out[0].kind, PlayoutKind::kFrame);
  EXPECT_EQ(stream.out[1].kind, PlayoutKind::kMissed);  // 0
  EXPECT_EQ(stream.out[2].kind, PlayoutKind::kMissed);  // 1
  EXPECT_EQ(stream.out[3].sequence, 2u);
  EXPECT_EQ(stream.out[3].kind, PlayoutKind::kFrame);
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, NothingComesOutTwiceAfterARestartOrAStop) {
  Stream stream;
  stream.run(0, 10);
  // A restart ahead (the sender skipped 1000 frames), then old numbers again: before the restart
  // plays they are duplicates of what came out, after it they are late. The old buffer took them
  // for a new stream start (within kCapacity/2 of the new first frame) or for another skip.
  const std::uint32_t skip = stream.next() + 1000;
  stream.send(skip);
  stream.send(skip - 3);  // inside the window before the new first frame: accepted, played first
  EXPECT_EQ(stream.buffer.stats().restarts, 1u);
  stream.send(5);
  EXPECT_EQ(stream.buffer.stats().duplicates, 1u);
  stream.tick(3);
  EXPECT_EQ(stream.count(skip - 3, PlayoutKind::kFrame), 1u);
  EXPECT_EQ(stream.count(skip, PlayoutKind::kFrame), 1u);
  stream.send(6);
  stream.send(skip);
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  EXPECT_EQ(stream.buffer.stats().duplicates, 2u);
  stream.tick(3);
  EXPECT_EQ(stream.count(5, PlayoutKind::kFrame), 1u);
  EXPECT_EQ(stream.count(6, PlayoutKind::kFrame), 1u);
  EXPECT_EQ(stream.buffer.stats().restarts, 1u);
  // The stream stops (silence), then an old frame is replayed: it does not start a stream.
  stream.tick(30);
  EXPECT_EQ(stream.buffer.stats().stops, 1u);
  stream.send(7);
  EXPECT_FALSE(stream.buffer.streaming());
  stream.tick(3);
  EXPECT_EQ(stream.count(7, PlayoutKind::kFrame), 1u);
  expect_each_once_in_order(stream);
  // reset() (a new connection) forgets the numbers: they start again.
  stream.buffer.reset();
  stream.out.clear();
  stream.send(7);
  stream.tick(3);
  EXPECT_EQ(stream.count(7, PlayoutKind::kFrame), 1u);
}

TEST(JitterBufferSequenceSpace, TimesOutOfRangeAreDroppedAndNeverStallTheSchedule) {
  Stream stream;
  stream.run(0, 10);
  // Sender times are doubles off the wire: not finite or beyond ±2^32 s, a frame cannot be
  // scheduled (late). At 1e17 s the old buffer's schedule froze (a period below the resolution)
  // and pop() returned kMissed for ever.
  const double inf = std::numeric_limits<double>::infinity();
  const std::uint32_t n = stream.next();
  for (const double t : {inf, -inf, std::numeric_limits<double>::quiet_NaN(), 1e17, -1e308}) {
    stream.buffer.push(n, frame_at_time(n, t), stream.now);
  }
  stream.buffer.push(n, frame_at(n), inf);  // an arrival out of range: the same
  EXPECT_EQ(stream.buffer.stats().late, 6u);
  EXPECT_EQ(stream.buffer.stats().restarts, 0u);
  // Within range but far off: a clock jump, played on a fresh schedule.
  stream.buffer.push(n, frame_at_time(n, JitterBuffer::kMaxTime), stream.now);
  EXPECT_EQ(stream.buffer.stats().restarts, 1u);
  stream.tick(5);
  EXPECT_EQ(stream.count(n, PlayoutKind::kFrame), 1u);
  EXPECT_EQ(stream.buffer.pop(std::numeric_limits<double>::quiet_NaN()).kind,
            PlayoutKind::kPending);
  stream.tick(30);
  EXPECT_LT(stream.out.size(), 100u) << "each period brings one result";
  expect_each_once_in_order(stream);
}

TEST(JitterBufferSequenceSpace, LateFramesFarOffTheScheduleDoNotMoveIt) {
  Stream stream;
  for (std::uint32_t s = 0; s < 10; ++s) {
    if (s < 5 || s > 7) {
      stream.send(s);  // 5, 6 and 7 are lost
    }
    stream.tick();
  }
  ASSERT_EQ(stream.count(7, PlayoutKind::kMissed), 1u);
  // They turn up late, stamped 4·10^6 s ahead (in range: the wire's largest time is 2^32 ms).
  // Taken as a late streak, the schedule would move 4·10^6 s back and every frame of that time
  // (10^8) would come out as missed at once.
  for (std::uint32_t s = 5; s < 8; ++s) {
    stream.buffer.push(s, frame_at_time(s, 4.0e6), stream.now);
  }
  EXPECT_EQ(stream.buffer.stats().late, 3u);
  EXPECT_EQ(stream.buffer.stats().offset_resets, 0u);
  int results = 0;
  for (Playout p = stream.buffer.pop(stream.now + kP);
       results < 1000 && (p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed);
       p = stream.buffer.pop(stream.now + kP)) {
    ++results;
  }
  EXPECT_LE(results, 2) << "one period, about one result";
}

TEST(JitterBufferSequenceSpace, ACallersClockGoingBackDoesNotMakeUpEveryPeriodSinceThen) {
  JitterBuffer buffer;
  // A frame arrives at 10^6 s, the clock goes back, the same frame arrives again at 1 s with
  // another sender time (a clock jump: a restart), and the next pop is at 10^6 s again: the
  // schedule is 10^6 s behind, 3·10^7 periods.
  buffer.push(5, frame_at_time(5, 100.0), 1.0e6);
  buffer.push(5, frame_at_time(5, 50.0), 1.0);
  EXPECT_EQ(buffer.stats().restarts, 1u);
  int results = 0;
  for (Playout p = buffer.pop(1.0e6 + 0.01);
       results < 1000 && (p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed);
       p = buffer.pop(1.0e6 + 0.01)) {
    ++results;
  }
  EXPECT_LE(results, 2) << "the frame, then the stream counts as stopped";
  EXPECT_EQ(buffer.stats().played, 1u);
  EXPECT_EQ(buffer.stats().stops, 1u);
  EXPECT_FALSE(buffer.streaming());
}

TEST(JitterBufferSequenceSpace, AfterAStopHalfTheSpaceFromTheLastResultIsOld) {
  // The last result was 8 (floor 9); after a stop, 8 + 2^31 is neither before nor after it (the
  // fuzzer found the buffer starting a stream there); 8 + 2^31 − 1 is after it and starts one.
  Stream stream;
  stream.run(0, 10);
  stream.tick(30);
  ASSERT_EQ(stream.buffer.stats().stops, 1u);
  const std::uint32_t last = stream.out.back().sequence;
  stream.send(last + kHalfSpace);
  EXPECT_FALSE(stream.buffer.streaming());
  EXPECT_EQ(stream.buffer.stats().late, 1u);
  stream.send(last + kHalfSpace - 1);
  EXPECT_TRUE(stream.buffer.streaming());
  stream.tick(3);
  EXPECT_EQ(stream.count(last + kHalfSpace - 1, PlayoutKind::kFrame), 1u);
  expect_each_once_in_order(stream);
}

}  // namespace
}  // namespace deixis::net
