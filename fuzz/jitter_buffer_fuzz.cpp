// libFuzzer target for the jitter buffer (net/jitter_buffer.h) driven by arbitrary sequence
// numbers and times: what a peer controls (sequence, sender time) and what the caller's clock
// gives (arrival, pop time), all decoded from the input as a list of steps:
//   op byte, low 3 bits: 0–2 push, 3–5 pop at a later time, 6 pop one frame period later,
//                         7 reset (bit 3 set) or nothing
//   push: bit 3: sequence = u32 (else the last pushed + i8)
//         bit 4: sender time = f64 bits (NaN, infinities, huge…) (else the last + i16 ms)
//         bit 5: arrival = f64 bits (else now + u8 ms)
//   pop:  bit 3: now = f64 bits (else now + u16 × 0.1 ms)
// A pop pops until kPending or kNoStream. After each step the buffer's promises must hold:
//   - results are in serial order (each within 2^31 after the one before, so no sequence number
//     comes out twice), one after the other except across a restart, a stop, or the first result
//     after reset(); a kFrame carries the frame pushed under its number; kMissed carries none;
//   - played and missed count the results; every frame played, late, duplicate or far ahead was
//     received; a pop loop ends (bounded results per call).
// Built with libFuzzer by the `fuzz` preset; in ordinary builds jitter_buffer_replay replays the
// committed corpus fuzz/corpus/jitter_buffer/.

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "net/jitter_buffer.h"

namespace {

using namespace deixis;
using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "jitter_buffer_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  bool empty() const { return at_ >= size_; }
  template <typename T>
  T take() {
    unsigned char bytes[sizeof(T)] = {};
    for (std::size_t i = 0; i < sizeof(T) && at_ < size_; ++i) {
      bytes[i] = data_[at_++];
    }
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

// What came out so far, to check each new result against.
struct Expect {
  bool any = false;  // a result since the last reset()
  std::uint32_t last = 0;
  std::uint64_t restarts = 0;  // stats at the last result
  std::uint64_t stops = 0;
  std::uint64_t frames = 0;
  std::uint64_t missed = 0;
};

// A pop loop yields the frames buffered and the missed periods the schedule lags behind, which
// the buffer bounds by stop_after + max_clock_jump + delay (about 50 at 30 Hz) whatever the
// clocks do. Far more than this means pop() does not move on.
constexpr int kMaxResultsPerLoop = 1000;

void drain(JitterBuffer& buffer, double now, Expect& expect) {
  for (int n = 0;; ++n) {
    check(n <= kMaxResultsPerLoop, "a pop loop ends");
    const Playout p = buffer.pop(now);
    if (p.kind == PlayoutKind::kNoStream) {
      check(!buffer.streaming(), "kNoStream: not streaming");
      return;
    }
    if (p.kind == PlayoutKind::kPending) {
      return;
    }
    check(p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed, "a known kind");
    if (p.kind == PlayoutKind::kFrame) {
      check(p.frame != nullptr, "a frame carries its frame");
      check(p.frame->head_target == static_cast<TargetId>(p.sequence), "the frame of its number");
      check(std::isfinite(p.waited), "waited is finite");
      ++expect.frames;
    } else {
      check(p.frame == nullptr, "missed carries no frame");
      ++expect.missed;
    }
    const JitterStats& s = buffer.stats();
    if (expect.any) {
      const std::uint32_t step = p.sequence - expect.last;
      check(step >= 1 && step < (std::uint32_t{1} << 31), "results in serial order, each once");
      if (s.restarts == expect.restarts && s.stops == expect.stops) {
        check(step == 1, "one after the other within a schedule");
      }
    }
    expect.any = true;
    expect.last = p.sequence;
    expect.restarts = s.restarts;
    expect.stops = s.stops;
  }
}

void check_stats(const JitterBuffer& buffer, const Expect& expect, std::uint64_t pushes) {
  const JitterStats& s = buffer.stats();
  check(s.received == pushes, "received counts the pushes");
  check(s.played == expect.frames, "played counts the frames");
  check(s.missed == expect.missed, "missed counts the missed results");
  check(s.played + s.late + s.duplicates + s.far_ahead <= s.received,
        "each frame received is played or dropped once at most");
  check(s.waited_max >= 0.0 && !std::isnan(s.waited_sum), "waiting times");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  JitterBuffer buffer;
  Expect expect;
  std::uint64_t pushes = 0;
  std::uint32_t sequence = 0;
  double sender_time = 1000.0;
  double now = 0.0;
  while (!in.empty()) {
    const auto op = in.take<std::uint8_t>();
    switch (op & 7u) {
      case 0:
      case 1:
      case 2: {
        sequence = (op & 0x08u) != 0
                       ? in.take<std::uint32_t>()
                       : sequence + static_cast<std::uint32_t>(
                                        static_cast<std::int32_t>(in.take<std::int8_t>()));
        sender_time = (op & 0x10u) != 0
                          ? std::bit_cast<double>(in.take<std::uint64_t>())
                          : sender_time + 1e-3 * static_cast<double>(in.take<std::int16_t>());
        const double arrival = (op & 0x20u) != 0
                                   ? std::bit_cast<double>(in.take<std::uint64_t>())
                                   : now + 1e-3 * static_cast<double>(in.take<std::uint8_t>());
        TrackingFrame frame;
        frame.time = sender_time;
        frame.head_target = static_cast<TargetId>(sequence);
        buffer.push(sequence, frame, arrival);
        ++pushes;
        if (!std::isfinite(sender_time)) {
          sender_time = 1000.0;  // pushed as it was; the next relative time starts from a sane one
        }
        break;
      }
      case 3:
      case 4:
      case 5:
        now = (op & 0x08u) != 0 ? std::bit_cast<double>(in.take<std::uint64_t>())
                                : now + 1e-4 * static_cast<double>(in.take<std::uint16_t>());
        drain(buffer, now, expect);
        if (!std::isfinite(now)) {
          now = 0.0;
        }
        break;
      case 6:
        now += buffer.config().frame_period;
        drain(buffer, now, expect);
        break;
      default:
        if ((op & 0x08u) != 0) {
          buffer.reset();
          check(!buffer.streaming(), "reset: not streaming");
          expect.any = false;  // the numbers may start again
        }
        break;
    }
    check_stats(buffer, expect, pushes);
  }
  return 0;
}
