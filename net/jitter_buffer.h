#pragma once
// The receiver's jitter buffer for one remote person's tracking (docs/protocol.md §8), on the
// caller's clock (every call takes `now`; nothing reads a clock).
//
// Each frame is played at   sender time + clock offset + delay,   where the clock offset is the
// transit (arrival − sender time) of the fastest frames: the third smallest over the last 4–8 s
// (the smallest until a window has 10 frames), so that one or two freak early arrivals cannot
// pull the schedule forward. Frames are played
// `delay` behind the fastest ones, so jitter up to `delay` costs nothing. Should frames keep
// arriving too late (kLateStreak in a row: the sender's clock stepped back, the route got longer),
// the offset starts again from the latest transit. Frames come out in sequence
// order; each sequence number comes out exactly once, as a frame or, when it did not arrive in
// time, as missed tracking (the translator then holds the last valid frame,
// docs/conventions.md#translator). A frame that arrives after its turn is late and dropped; one
// that arrives twice is a duplicate and dropped. When nothing has arrived for `stop_after`, the
// stream is reported stopped (kNoStream: hide the avatar, never freeze it) until frames arrive
// again.
//
// Sequence numbers come from the network: every comparison is serial-number arithmetic (RFC 1982)
// on unsigned 32-bit differences, so wrapping at 2^32 is normal and no value, however far off,
// can overflow or shift out of range. Relative to the next frame due (or to the first frame of a
// stream that has not started playing, which accepts kCapacity/2 frames before it):
//   - 1 ≤ behind ≤ 2^31 (exactly half the space away counts as behind: RFC 1982 leaves it
//     undefined, and dropping is the safe choice): an old frame, a duplicate if it came out as a
//     frame among the last 64 results, otherwise late; dropped either way;
//   - kCapacity ≤ ahead < kMaxSkip (kCapacity/2 before the stream plays): the sender skipped
//     ahead, the schedule restarts from this frame (stats().restarts);
//   - kMaxSkip ≤ ahead < 2^31 − 1: too far ahead to believe (the sender sends 30 frames a second
//     and its connection is renewed, with new numbers, long before it could skip that far):
//     dropped (stats().far_ahead). It does not keep the stream alive either, so a sender that
//     really is there is followed after stop_after, when the stream has stopped and starts again
//     from it. (2^31 − 1 ahead of the next frame is half the space from the last result: old.)
// Results only move forward: until reset(), only frames strictly after the last result (1 to
// 2^31 − 1 after it) are accepted, even after a restart or a stop (the rest are old: duplicate or
// late), so each result is after the one before in serial order and no sequence number comes out
// twice unless the results travel round the whole 2^32 space (which takes at least 2^16 restarts
// or two stops). Times are never converted to integers. A frame whose sender time or arrival is
// not finite or beyond ±kMaxTime is dropped as late, and pop() at such a time is kPending: with
// every time within 2^32 s, a frame period is far above a double's resolution, so each result
// moves the schedule on by about a period and a call loop of pop() always ends (a sender time of
// 1e17 s would freeze the schedule and yield kMissed for ever). The wire carries sender times as
// 32-bit milliseconds (under 2^22 s). A call loop of pop() also stays short when the caller's
// clock is not monotonic: a missing frame overdue by more than stop_after + max_clock_jump +
// delay (which a live stream on a monotonic clock never is) stops the stream rather than make up
// every period in between; and late frames whose transit is beyond max_clock_jump from the
// schedule do not count towards kLateStreak.
//
// Fixed capacity, no allocation after construction.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include "core/tracking.h"

namespace deixis::net {

struct JitterConfig {
  double frame_period = 1.0 / 30.0;  // s: the 30 Hz tick (docs/conventions.md#rates-and-windows)
  // Playout delay behind the least-delayed frames (s). 50 ms: 1.5 ticks; absorbs jitter up to
  // 50 ms (docs/protocol.md, "Jitter buffer", and the figure in bench/net_bench.cpp).
  double delay = 0.050;
  double stop_after = 0.5;      // s of silence before the stream counts as stopped
  double offset_window = 4.0;   // s; the offset comes from the last 1–2 windows of this length
  double max_clock_jump = 1.0;  // s; a transit this far off restarts the schedule
};

enum class PlayoutKind : std::uint8_t {
  kNoStream,  // no stream (not started, or stopped): hide the avatar
  kPending,   // the next frame is not due yet: nothing new
  kFrame,     // the next frame, in sequence order
  kMissed,    // the next frame did not arrive in time: hold the last valid frame
};

struct Playout {
  PlayoutKind kind = PlayoutKind::kNoStream;
  std::uint32_t sequence = 0;            // kFrame and kMissed
  const TrackingFrame* frame = nullptr;  // kFrame: valid until the next push() or pop()
  double waited = 0.0;                   // kFrame: seconds between arrival and playout
};

struct JitterStats {
  std::uint64_t received = 0;       // frames pushed
  std::uint64_t played = 0;         // kFrame results
  std::uint64_t missed = 0;         // kMissed results
  std::uint64_t late = 0;           // arrived after their turn (played as missed), dropped
  std::uint64_t duplicates = 0;     // arrived twice, dropped
  std::uint64_t stops = 0;          // streams reported stopped
  std::uint64_t restarts = 0;       // schedules restarted: a clock jump or a sequence far ahead
  std::uint64_t far_ahead = 0;      // too far ahead to believe (kMaxSkip or more), dropped
  std::uint64_t offset_resets = 0;  // the offset started again after kLateStreak late frames
  double waited_sum = 0.0;          // over played frames (s)
  double waited_max = 0.0;
};

class JitterBuffer {
 public:
  static constexpr std::uint32_t kCapacity = 32;  // frames: about 1 s at 30 Hz
  // Times (s) beyond ±kMaxTime are not scheduled: 2^32 s, 136 years.
  static constexpr double kMaxTime = 4294967296.0;
  // The farthest skip ahead that restarts the schedule: 36 min of frames at 30 Hz.
  static constexpr std::uint32_t kMaxSkip = std::uint32_t{1} << 16;
  static constexpr int kLateStreak = 3;
  static constexpr int kRobustAfter = 10;  // frames in a window before it discounts two

  explicit JitterBuffer(const JitterConfig& config = {}) : config_(config) {}

  void push(std::uint32_t sequence, const TrackingFrame& frame, double arrival);
  // The next result at time `now`. Call until it returns kPending or kNoStream: each frame
  // period normally yields one kFrame or kMissed.
  Playout pop(double now);
  // Forget the stream (a new connection restarts its sequence numbers) and the sequence numbers
  // that came out; statistics are kept.
  void reset();

  bool streaming() const { return anchored_; }
  const JitterStats& stats() const { return stats_; }
  const JitterConfig& config() const { return config_; }

 private:
  // The three smallest transits of a window, ascending.
  struct FastestTransits {
    static constexpr int kMaxCount = 1 << 30;  // count saturates here (arrivals are untrusted)
    std::array<double, 3> value{};
    int count = 0;  // frames in the window (value holds min(count, 3) of them)
    void add(double transit);
    // The third smallest once the window has enough frames for two to be freaks; before, the
    // smallest.
    double robust() const { return count >= kRobustAfter ? value[2] : value[0]; }
  };

  struct Slot {
    bool full = false;
    std::uint32_t sequence = 0;
    double arrival = 0.0;
    TrackingFrame frame;
  };

  Slot& slot(std::uint32_t sequence) { return slots_[sequence % kCapacity]; }
  bool holds(std::uint32_t sequence) const {
    const Slot& s = slots_[sequence % kCapacity];
    return s.full && s.sequence == sequence;
  }
  double offset() const;
  double play_time(const Slot& s) const;
  void update_offset(double transit, double arrival);
  void anchor(std::uint32_t sequence, double transit, double arrival);
  void forget();  // the stream stopped: what is buffered goes, the results' floor stays
  bool below_floor(std::uint32_t sequence) const;
  void drop_old(std::uint32_t sequence, double transit, double arrival);
  bool start_playing(double now);
  Playout advance(Playout result, double sender_time);
  double missed_sender_time() const;  // the estimated sender time of the missing next_

  JitterConfig config_;
  std::array<Slot, kCapacity> slots_{};
  JitterStats stats_;

  bool anchored_ = false;  // frames have arrived since the last reset or stop
  bool playing_ = false;   // next_ is defined
  std::uint32_t anchor_ = 0;
  std::uint32_t next_ = 0;
  bool has_last_ = false;
  // The sender time of the last result (estimated for a missed frame): the next one is due a
  // frame period later, on the current offset, so a changed offset moves it too.
  double last_sender_time_ = 0.0;
  // The sequence number after the last result (frame or missed), once there was one since the
  // last reset(): nothing before it is accepted again. While playing, floor_ == next_ once the
  // stream has produced a result.
  bool has_floor_ = false;
  std::uint32_t floor_ = 0;
  std::uint64_t played_mask_ = 0;  // bit i: floor_ − 1 − i came out as a frame
  double last_arrival_ = 0.0;
  double window_start_ = 0.0;
  FastestTransits current_;
  FastestTransits previous_;
  int late_streak_ = 0;
  // Frames below this were given up on before the last offset reset; arriving late is expected of
  // them and says nothing new.
  std::uint32_t streak_floor_ = 0;
};

}  // namespace deixis::net
