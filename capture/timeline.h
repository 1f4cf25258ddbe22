#pragma once
// Time courses of the motion model.
//
// Movements follow the minimum-jerk profile (Flash & Hogan 1985): the smoothest point-to-point
// movement, with the bell-shaped speed profile of human reaches. Their durations grow with
// distance by Fitts' law (Fitts 1954, Shannon form: a + b·log2(1 + D/W)).
//
// A Track holds one channel (torso, head, gaze, a wrist) as a list of moves: each move goes from
// the previous value to a new one over [start, end] and holds afterwards. The values are resolved
// by the caller (they may live in the torso frame or the world), so a Track only answers "between
// which two values, and how far along".
//
// A Ramp is a piecewise-linear label course (paper §III.B: "intermediate values ... by linear
// interpolation"); two keys at the same time make a step.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <vector>

namespace deixis::capture {

// Position along a minimum-jerk movement at normalised time tau ∈ [0, 1].
inline double minimum_jerk(double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  return tau * tau * tau * (10.0 + tau * (-15.0 + 6.0 * tau));
}

// Fitts' law movement time for amplitude `distance` and target width `width` (same unit).
inline double fitts_duration(double distance, double width, double intercept, double slope) {
  return intercept + slope * std::log2(1.0 + std::max(distance, 0.0) / width);
}

template <class Value>
class Track {
 public:
  struct Move {
    double start;
    double end;
    Value value;
  };
  struct Sample {
    const Value* from;
    const Value* to;
    double s;  // minimum-jerk progress from `from` to `to`
  };

  explicit Track(Value initial) {
    moves_.push_back({-std::numeric_limits<double>::infinity(),
                      -std::numeric_limits<double>::infinity(), std::move(initial)});
  }

  // Moves to `value` over [start, start + duration]. Moves never overlap: a move asked to start
  // before the previous one ends starts when it ends.
  void move(double start, double duration, Value value) {
    start = std::max(start, moves_.back().end);
    moves_.push_back({start, start + std::max(duration, 1e-3), std::move(value)});
  }
  // Replaces the value held after the last move (a hold that changes only how it is resolved).
  Value& last() { return moves_.back().value; }
  const Value& last() const { return moves_.back().value; }
  double end_time() const { return moves_.back().end; }
  const std::vector<Move>& moves() const { return moves_; }

  Sample at(double t) const {
    // The last move that has started by t.
    auto it = std::upper_bound(moves_.begin() + 1, moves_.end(), t,
                               [](double time, const Move& m) { return time < m.start; });
    const std::size_t k = static_cast<std::size_t>(it - moves_.begin()) - 1;
    const Move& m = moves_[k];
    if (k == 0 || t >= m.end) {
      return {&m.value, &m.value, 1.0};
    }
    return {&moves_[k - 1].value, &m.value, minimum_jerk((t - m.start) / (m.end - m.start))};
  }

 private:
  std::vector<Move> moves_;
};

// A piecewise-linear course in time (the progression labels).
class Ramp {
 public:
  explicit Ramp(float initial) : keys_{{-std::numeric_limits<double>::infinity(), initial}} {}

  // Holds the current value until `t`, then goes linearly to `value` at `t + duration`
  // (duration 0: a step at t).
  void to(double t, double duration, float value) {
    t = std::max(t, keys_.back().time);
    if (keys_.back().value != value || duration > 0) {
      keys_.push_back({t, keys_.back().value});
      keys_.push_back({t + std::max(duration, 0.0), value});
    }
  }
  float value_at(double t) const {
    // After a step (two keys at one time) the later key wins.
    auto it = std::upper_bound(keys_.begin(), keys_.end(), t,
                               [](double time, const Key& k) { return time < k.time; });
    const Key& a = *(it - 1);
    if (it == keys_.end() || it->time == a.time || std::isinf(a.time)) {
      return a.value;
    }
    const double u = (t - a.time) / (it->time - a.time);
    return static_cast<float>(static_cast<double>(a.value) +
                              u * static_cast<double>(it->value - a.value));
  }
  float last() const { return keys_.back().value; }
  double last_time() const { return keys_.back().time; }

  struct Key {
    double time;
    float value;
  };
  const std::vector<Key>& keys() const { return keys_; }

 private:
  std::vector<Key> keys_;
};

// A piecewise-constant course (which target is the head or hand target).
template <class Value>
class Steps {
 public:
  explicit Steps(Value initial) : steps_{{-std::numeric_limits<double>::infinity(), initial}} {}
  void set(double t, Value v) {
    t = std::max(t, steps_.back().first);
    steps_.push_back({t, v});
  }
  const Value& at(double t) const {
    auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                               [](double time, const auto& s) { return time < s.first; });
    return (it - 1)->second;
  }
  const Value& last() const { return steps_.back().second; }

 private:
  std::vector<std::pair<double, Value>> steps_;
};

}  // namespace deixis::capture
