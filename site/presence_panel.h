#pragma once
// The presence panel's text (issue 25 part 5, docs/xr.md "Presence panel"): a first line with
// the session's state, then one line per remote person (site/link_health.h: live or not, round
// trip, jitter-buffer delay, frames dropped in the last seconds). `deixis xr` shows it head-locked
// (render/scene.h, HeadPanel) and prints its last lines in the summary; the simulator's panel
// shows the same person lines.
//
// Rebuilt at most every kRefresh seconds into fixed buffers, so a headset's frame loop can ask
// for it every frame without allocating and without the figures flickering.

#include <array>
#include <cstddef>
#include <span>
#include <string_view>

#include "site/live_peer.h"

namespace deixis::site {

class PresencePanel {
 public:
  static constexpr std::size_t kMaxPeople = 8;  // lines beyond the title; more are counted
  static constexpr std::size_t kLineChars = 128;
  static constexpr double kRefresh = 0.5;  // s

  // Rebuilds the lines from `peer` when kRefresh has passed since the last rebuild (or `force`).
  void update(double now, const LivePeer& peer, bool force = false);
  // Title first, then one line per person present (as of the last rebuild).
  std::span<const std::string_view> lines() const { return std::span(lines_).first(count_); }

 private:
  void set_line(std::size_t i, std::size_t length);

  std::array<std::array<char, kLineChars>, kMaxPeople + 2> text_{};
  std::array<std::string_view, kMaxPeople + 2> lines_{};
  std::array<LivePerson, 32> people_{};  // listed (a room holds at most 16 members)
  std::size_t count_ = 0;
  double rebuilt_ = 0.0;
  bool built_ = false;
};

// The session's state in a few words: "waiting for the other site", "connected", "entering the
// room", "in the room".
std::string_view session_state_words(const LivePeer& peer);

}  // namespace deixis::site
