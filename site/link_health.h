#pragma once
// How each remote person's link is doing, as the presence panels say it (the headset's
// head-locked panel, the simulator's panel; docs/xr.md "Presence panel", decision 84): whether
// their avatar is live, the round trip, how long their frames wait in our jitter buffer, and how
// many of their frames were due over the last few seconds and not played (lost or late).
//
// The figures come from the counters the session keeps anyway (net::JitterStats): a LinkWindow
// samples them twice a second and differences the newest against the oldest sample within
// kWindow, so a loss burst shows for a few seconds and then clears. Nothing here allocates.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "net/jitter_buffer.h"

namespace deixis::site {

enum class LinkState : std::uint8_t {
  kWaiting,  // present, their first frame not played yet (or their avatar not ready)
  kLive,     // their avatar is shown
  kStalled,  // present, but their stream stopped (nothing for JitterConfig::stop_after): hidden
};
std::string_view link_state_name(LinkState state);  // "waiting", "live", "stalled"

struct LinkFigures {
  LinkState state = LinkState::kWaiting;
  // Round trip in ms to the other site (direct session) or, in a room, to the relay (the room's
  // members reach each other only through it; ENet's estimate); -1 while not connected.
  std::int64_t round_trip_ms = -1;
  bool via_relay = false;
  // Over the window: the mean time a played frame waited in the jitter buffer (ms; negative when
  // none was played), frames due (played or missed) and frames missed (lost or late).
  double buffer_delay_ms = -1.0;
  std::uint64_t due = 0;
  std::uint64_t dropped = 0;
  double window_s = 0.0;  // the window's length so far: kWindow once the person stayed that long
};

class LinkWindow {
 public:
  static constexpr double kWindow = 5.0;    // s the figures cover
  static constexpr double kInterval = 0.5;  // s between samples

  // Forget everything (another person, or the same one met again).
  void reset();
  // The person's counters at `now` (call every tick; a sample is kept every kInterval).
  void update(double now, const net::JitterStats& stats);
  // The figures over the last kWindow (up to the latest update). State and round trip are the
  // caller's: they do not come from the counters.
  LinkFigures figures() const;

 private:
  struct Sample {
    double time = 0.0;
    std::uint64_t played = 0;
    std::uint64_t missed = 0;
    double waited_sum = 0.0;
  };
  static constexpr std::size_t kSamples = static_cast<std::size_t>(kWindow / kInterval) + 1;
  static Sample sample_of(double now, const net::JitterStats& stats);

  std::array<Sample, kSamples> ring_{};
  std::size_t count_ = 0;  // samples kept (≤ kSamples)
  std::size_t next_ = 0;   // where the next one goes
  Sample latest_{};
  bool started_ = false;
};

// One person's line for a panel, e.g.
//   "B: live, rtt 42 ms, buffer 51 ms, dropped 3 of 150 in 5 s"
// into `out` (truncated to fit, always terminated); returns the length written. No allocation.
std::size_t format_link_line(std::string_view site, const LinkFigures& link, std::span<char> out);

}  // namespace deixis::site
