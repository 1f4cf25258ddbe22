#include "net/jitter_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace deixis::net {

namespace {

// Serial-number arithmetic (RFC 1982) on 32-bit sequence numbers, in unsigned types only: a
// difference is taken modulo 2^32 and classified by comparisons, never negated or converted to a
// signed type, so any pair of values is defined.
constexpr std::uint32_t kHalfSpace = std::uint32_t{1} << 31;

// `a` is `b` or comes after it: `a` is less than half the sequence space ahead. Exactly half the
// space away counts as before.
bool at_or_after(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::uint32_t>(a - b) < kHalfSpace;
}

// Frames a not-yet-playing stream accepts before its first frame; a playing stream accepts none
// before the next frame due.
constexpr std::uint32_t kSlackBefore = JitterBuffer::kCapacity / 2;
// Not NaN, not infinite, not beyond ±kMaxTime.
bool within_time_range(double t) {
  return std::abs(t) <= JitterBuffer::kMaxTime;
}

// Results remembered as played (the bits of played_mask_).
constexpr std::uint32_t kMaskBits = 64;

}  // namespace

void JitterBuffer::FastestTransits::add(double transit) {
  if (count < 3) {
    value[static_cast<std::size_t>(count++)] = transit;
    std::sort(value.begin(), value.begin() + count);
    return;
  }
  if (count < kMaxCount) {
    ++count;
  }
  if (transit < value[2]) {
    value[2] = transit;
    std::sort(value.begin(), value.end());
  }
}

double JitterBuffer::offset() const {
  // A window with few frames does not speak yet, unless there is no other.
  if (previous_.count == 0) {
    return current_.robust();
  }
  return current_.count >= kRobustAfter ? std::min(previous_.robust(), current_.robust())
                                        : previous_.robust();
}

double JitterBuffer::play_time(const Slot& s) const {
  return s.frame.time + offset() + config_.delay;
}

void JitterBuffer::update_offset(double transit, double arrival) {
  // Two alternating windows: the offset follows a clock drift or a longer route within 1–2
  // windows, while one slow frame never moves it and two fast ones do not either.
  if (arrival - window_start_ >= config_.offset_window) {
    previous_ = current_;
    current_ = FastestTransits{};
    window_start_ = arrival;
  }
  current_.add(transit);
}

void JitterBuffer::anchor(std::uint32_t sequence, double transit, double arrival) {
  for (Slot& s : slots_) {
    s.full = false;
  }
  anchored_ = true;
  playing_ = false;
  has_last_ = false;
  anchor_ = sequence;
  streak_floor_ = sequence;
  window_start_ = arrival;
  current_ = FastestTransits{};
  previous_ = FastestTransits{};
  late_streak_ = 0;
  current_.add(transit);
}

void JitterBuffer::forget() {
  for (Slot& s : slots_) {
    s.full = false;
  }
  anchored_ = false;
  playing_ = false;
  has_last_ = false;
}

void JitterBuffer::reset() {
  forget();
  has_floor_ = false;
  played_mask_ = 0;
}

bool JitterBuffer::below_floor(std::uint32_t sequence) const {
  // Accepted: strictly after the last result (floor_ − 1) in serial order, less than half the
  // space after it. floor_ + 2^31 − 1 is exactly half the space from the last result: neither
  // before nor after it, so it counts as old too.
  return has_floor_ && static_cast<std::uint32_t>(sequence - floor_) >= kHalfSpace - 1;
}

void JitterBuffer::drop_old(std::uint32_t sequence, double transit, double arrival) {
  // 1 = the last result; 0 or ≥ 2^31 when the frame is not before floor_ (then not a duplicate).
  const std::uint32_t age = floor_ - sequence;
  if (has_floor_ && age >= 1 && age <= kMaskBits && ((played_mask_ >> (age - 1)) & 1u) != 0) {
    ++stats_.duplicates;
    return;
  }
  ++stats_.late;
  // Only a transit near the schedule says that it runs ahead of the frames. One beyond
  // max_clock_jump is a clock jump, which frames not yet due restart on; taken from late frames it
  // would move the schedule by up to the whole time range, and every frame in between would come
  // out as missed at once (2^32 s: 10^11 results).
  if (playing_ && at_or_after(sequence, streak_floor_) &&
      std::abs(transit - offset()) <= config_.max_clock_jump && ++late_streak_ >= kLateStreak) {
    // The schedule runs ahead of the frames: start the offset again from where they are.
    ++stats_.offset_resets;
    late_streak_ = 0;
    streak_floor_ = next_;
    window_start_ = arrival;
    current_ = FastestTransits{};
    previous_ = FastestTransits{};
    current_.add(transit);
  }
}

void JitterBuffer::push(std::uint32_t sequence, const TrackingFrame& frame, double arrival) {
  ++stats_.received;
  if (!within_time_range(arrival) || !within_time_range(frame.time)) {
    ++stats_.late;  // cannot be scheduled; the decoder never produces this
    return;
  }
  const double transit = arrival - frame.time;
  // At or before the last result: it came out already (as a frame or as missed tracking).
  const bool old = below_floor(sequence);
  bool fresh = false;  // an anchor counts this frame's transit already
  if (!anchored_ && !old) {
    anchor(sequence, transit, arrival);
    fresh = true;
  }
  // How far the frame is behind / ahead of the next one due (or, before the stream plays, of its
  // first frame), modulo 2^32; exactly one of them is below 2^31 unless both are 2^31.
  const std::uint32_t reference = playing_ ? next_ : anchor_;
  const std::uint32_t behind = reference - sequence;
  const std::uint32_t ahead = sequence - reference;
  if (anchored_ && !old && ahead >= kMaxSkip && ahead < kHalfSpace) {
    ++stats_.far_ahead;  // not believed, and no sign that the stream lives
    return;
  }
  if (anchored_) {
    last_arrival_ = std::max(last_arrival_, arrival);  // even a late frame shows the stream lives
  }
  const std::uint32_t slack = playing_ ? 0 : kSlackBefore;
  const std::uint32_t limit = playing_ ? kCapacity : kSlackBefore;
  if (old || (behind > slack && behind <= kHalfSpace)) {
    drop_old(sequence, transit, arrival);
    return;
  }
  // Far ahead (the sender skipped), or a transit far from the estimate (the sender's clock jumped
  // or wrapped): what is buffered no longer fits the schedule, so start a new one.
  if ((ahead >= limit && ahead < kMaxSkip) ||
      std::abs(transit - offset()) > config_.max_clock_jump) {
    ++stats_.restarts;
    anchor(sequence, transit, arrival);
    fresh = true;
  }
  if (!fresh) {
    update_offset(transit, arrival);
  }
  Slot& s = slot(sequence);
  if (s.full && s.sequence == sequence) {
    ++stats_.duplicates;
    return;
  }
  late_streak_ = 0;
  s.full = true;
  s.sequence = sequence;
  s.arrival = arrival;
  s.frame = frame;
}

bool JitterBuffer::start_playing(double now) {
  // Start with the lowest sequence number buffered, once the first frame is due.
  bool any = false;
  std::uint32_t lowest = 0;
  bool due = false;
  for (const Slot& s : slots_) {
    if (!s.full) {
      continue;
    }
    if (!any || !at_or_after(s.sequence, lowest)) {
      lowest = s.sequence;
    }
    any = true;
    due = due || now >= play_time(s);
  }
  if (!due) {
    return false;
  }
  playing_ = true;
  next_ = lowest;
  return true;
}

double JitterBuffer::missed_sender_time() const {
  // A frame that has not come is given up on when it would have been due: its sender time is
  // estimated from the last result and from the next frame that is here, whichever is earlier.
  double sender_time = has_last_ ? last_sender_time_ + config_.frame_period
                                 : std::numeric_limits<double>::infinity();
  for (std::uint32_t k = 1; k < kCapacity; ++k) {
    if (holds(next_ + k)) {
      const Slot& later = slots_[(next_ + k) % kCapacity];
      sender_time = std::min(sender_time, later.frame.time - k * config_.frame_period);
      break;
    }
  }
  return sender_time;
}

Playout JitterBuffer::advance(Playout result, double sender_time) {
  // Sequence numbers a restart jumped over since the last result came out as nothing: shift them
  // out of the mask (a shift by the mask's width or more would be undefined).
  const std::uint32_t skipped = has_floor_ ? next_ - floor_ : kMaskBits;
  played_mask_ = skipped >= kMaskBits ? 0 : played_mask_ << skipped;
  played_mask_ = (played_mask_ << 1) | (result.kind == PlayoutKind::kFrame ? 1u : 0u);
  has_last_ = true;
  last_sender_time_ = sender_time;
  ++next_;
  floor_ = next_;
  has_floor_ = true;
  return result;
}

Playout JitterBuffer::pop(double now) {
  if (!anchored_) {
    return {};
  }
  if (!within_time_range(now)) {
    return {PlayoutKind::kPending};
  }
  if (now - last_arrival_ > config_.stop_after) {
    ++stats_.stops;
    forget();
    return {};
  }
  if (!playing_ && !start_playing(now)) {
    return {PlayoutKind::kPending};
  }
  if (holds(next_)) {
    Slot& s = slot(next_);
    const double at = play_time(s);
    if (now < at) {
      return {PlayoutKind::kPending};
    }
    s.full = false;
    const double waited = now - s.arrival;
    ++stats_.played;
    stats_.waited_sum += waited;
    stats_.waited_max = std::max(stats_.waited_max, waited);
    return advance({PlayoutKind::kFrame, next_, &s.frame, waited}, s.frame.time);
  }
  const double sender_time = missed_sender_time();
  const double due = sender_time + offset() + config_.delay;
  if (now < due) {
    return {PlayoutKind::kPending};
  }
  if (now - due > config_.stop_after + config_.max_clock_jump + config_.delay) {
    // The schedule lags the clock further than a live stream's can (frames arrived with times
    // from before an earlier arrival: the caller's clock is not monotonic). Making up every
    // period in between, one missed result each, could take 10^11 results: the stream counts
    // as stopped instead, and starts again with the next frame.
    ++stats_.stops;
    forget();
    return {};
  }
  ++stats_.missed;
  return advance({PlayoutKind::kMissed, next_, nullptr, 0.0}, sender_time);
}

}  // namespace deixis::net
