#include "net/jitter_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace deixis::net {

namespace {

// Signed distance from `b` to `a` in sequence space (wraps at 2^32).
std::int32_t distance(std::uint32_t a, std::uint32_t b) {
  return static_cast<std::int32_t>(a - b);
}

constexpr std::int32_t kHalf = static_cast<std::int32_t>(JitterBuffer::kCapacity / 2);
constexpr std::int32_t kFull = static_cast<std::int32_t>(JitterBuffer::kCapacity);

}  // namespace

void JitterBuffer::FastestTransits::add(double transit) {
  if (count < 3) {
    value[static_cast<std::size_t>(count++)] = transit;
    std::sort(value.begin(), value.begin() + count);
    return;
  }
  ++count;
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
  played_mask_ = 0;
  anchor_ = sequence;
  streak_floor_ = sequence;
  window_start_ = arrival;
  current_ = FastestTransits{};
  previous_ = FastestTransits{};
  late_streak_ = 0;
  current_.add(transit);
}

void JitterBuffer::reset() {
  for (Slot& s : slots_) {
    s.full = false;
  }
  anchored_ = false;
  playing_ = false;
  has_last_ = false;
  played_mask_ = 0;
}

void JitterBuffer::push(std::uint32_t sequence, const TrackingFrame& frame, double arrival) {
  ++stats_.received;
  const double transit = arrival - frame.time;
  if (!std::isfinite(transit)) {
    ++stats_.late;  // cannot be scheduled; the decoder never produces this
    return;
  }
  bool fresh = false;  // an anchor counts this frame's transit already
  if (!anchored_) {
    anchor(sequence, transit, arrival);
    fresh = true;
  }
  last_arrival_ = std::max(last_arrival_, arrival);  // even a late frame shows the stream lives

  const std::int32_t d = distance(sequence, playing_ ? next_ : anchor_);
  const std::int32_t lowest = playing_ ? 0 : -kHalf;
  const std::int32_t limit = playing_ ? kFull : kHalf;
  if (d < lowest) {
    const std::int32_t age = -d;  // 1 = the frame just played (or missed)
    if (playing_ && age <= 64 && ((played_mask_ >> (age - 1)) & 1u) != 0) {
      ++stats_.duplicates;
    } else {
      ++stats_.late;
      if (distance(sequence, streak_floor_) >= 0 && ++late_streak_ >= kLateStreak) {
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
    return;
  }
  // Far ahead (the sender skipped), or a transit far from the estimate (the sender's clock jumped
  // or wrapped): what is buffered no longer fits the schedule, so start a new one.
  if (d >= limit || std::abs(transit - offset()) > config_.max_clock_jump) {
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
    if (!any || distance(s.sequence, lowest) < 0) {
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
  played_mask_ = (played_mask_ << 1) | (result.kind == PlayoutKind::kFrame ? 1u : 0u);
  has_last_ = true;
  last_sender_time_ = sender_time;
  ++next_;
  return result;
}

Playout JitterBuffer::pop(double now) {
  if (!anchored_) {
    return {};
  }
  if (now - last_arrival_ > config_.stop_after) {
    ++stats_.stops;
    reset();
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
  if (now < sender_time + offset() + config_.delay) {
    return {PlayoutKind::kPending};
  }
  ++stats_.missed;
  return advance({PlayoutKind::kMissed, next_, nullptr, 0.0}, sender_time);
}

}  // namespace deixis::net
