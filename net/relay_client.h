#pragma once
// A room member's connection to a relay (docs/relay.md): the relay forwards opaque payloads
// between the members of a room and tells each who is there, who joined and who left. It sees a
// room only by its token (a hash of the room's name) and never parses a payload; what the
// members say to each other, sealed or not, is the room layer's business (net/room_session.h,
// docs/rooms-protocol.md).
//
// Non-blocking, on the caller's clock: poll(now) handles a bounded number of link events and the
// timers, and reports through a RelayListener. When the relay is lost (no keepalive within
// kRelaySilenceTimeout, or the connection drops) the client says so (on_relay_lost) and
// reconnects by itself with a backoff starting at kRelayReconnectMin; after each new welcome it
// calls on_relay_ready again, and the listener enters the room again (the relay gives it a new
// member id). Refusals that retrying cannot fix (room full, another relay version, not a relay at
// all) end the client for good; the others (relay full, try later, flooding, protocol) are retried.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "net/drop_log.h"
#include "net/link.h"
#include "net/protocol.h"

namespace spdlog {
class logger;
}

namespace deixis::net {

class EnetLink;

// A member of a room, as the relay names it: 1–254, unique among the room's current members.
// A member that leaves and comes back (or reconnects after the relay restarted) gets a fresh id.
using MemberId = std::uint8_t;
inline constexpr MemberId kNoMember = 0;
inline constexpr MemberId kAllMembers = 255;  // send only: everyone else in the room
inline constexpr MemberId kFirstMember = 1;
inline constexpr MemberId kLastMember = 254;

inline constexpr std::size_t kRoomParamsMax = 64;        // opaque to the relay
inline constexpr std::size_t kAnnounceMax = 128;         // opaque to the relay
inline constexpr std::size_t kRelayPayloadMax = 30'000;  // opaque payload per forward

// The relay sees this, never the room's name.
using RoomToken = std::array<std::uint8_t, 32>;
// BLAKE2b-256("deixis room" ‖ name).
RoomToken room_token(std::string_view room_name);

struct RoomMember {
  MemberId id = kNoMember;
  std::span<const std::uint8_t> announce;
};

enum class RelayRefusal : std::uint8_t {
  kRoomFull = 0,   // the room has --max-people members (final)
  kRelayFull = 1,  // the relay holds as many rooms or connections as it may (retried)
  kVersion = 2,    // the relay speaks another relay protocol version (final)
  kTryLater = 3,   // too many pending connections from this address (retried)
  kProtocol = 4,   // a message out of order (retried)
  kFlooding = 5,   // sent more than the member's budget (retried, after the backoff)
  kNotARelay = 6,  // the address answers as a direct-session host, not a relay (final)
};
inline constexpr std::uint8_t kMaxRelayRefusal = 6;
// Words for the user: "room full", "not a relay (a direct-session host?)", …
std::string_view describe(RelayRefusal why);
// Refusals that retrying cannot fix: the client stops.
bool is_final(RelayRefusal why);

class RelayListener {  // spans are valid only during the call
 public:
  virtual ~RelayListener() = default;
  virtual void on_relay_ready() = 0;  // relay welcome accepted: call enter() now (fresh announce)
  virtual void on_entered(MemberId self, std::span<const std::uint8_t> room_params,
                          std::span<const RoomMember> already_there) = 0;
  virtual void on_member_joined(const RoomMember& member) = 0;
  virtual void on_member_left(MemberId id) = 0;
  virtual void on_payload(MemberId from, Channel channel,
                          std::span<const std::uint8_t> payload) = 0;
  virtual void on_refused(RelayRefusal why) = 0;  // kRoomFull, kVersion, kNotARelay: final
  virtual void on_relay_lost() = 0;               // everyone is gone; the client reconnects itself
};

// Timers (s). The relay sends a keepalive every kRelayKeepaliveInterval when it has nothing else
// to send; a client that hears nothing for kRelaySilenceTimeout counts the relay as lost.
inline constexpr double kRelayKeepaliveInterval = 0.5;
inline constexpr double kRelaySilenceTimeout = 1.5;
inline constexpr double kRelayReconnectMin = 0.2;
inline constexpr double kRelayReconnectMax = 2.0;
inline constexpr double kRelayConnectTimeout = 1.5;  // per attempt, until the welcome

struct RelayClientOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 7351;
  RoomToken room{};
  // Added: where to connect from (tests play other machines from other loopback addresses), and
  // the log.
  std::string local_address;
  std::shared_ptr<spdlog::logger> logger;  // null: spdlog's default logger
};

struct RelayClientStats {
  std::uint64_t attempts = 0;    // connection attempts
  std::uint64_t welcomes = 0;    // relay welcomes accepted
  std::uint64_t entries = 0;     // rooms entered
  std::uint64_t relay_lost = 0;  // times the relay was lost (silence or disconnect)
  std::uint64_t refusals = 0;    // refusals heard
  std::uint64_t sent = 0;        // forwards sent
  std::uint64_t send_failures = 0;
  std::uint64_t received = 0;    // payloads handed to the listener
  std::uint64_t bytes_sent = 0;  // payload bytes
  std::uint64_t bytes_received = 0;
};

class RelayClient {
 public:
  // Resolves the relay's address and makes the first attempt; throws deixis::Error when the
  // address cannot be resolved.
  RelayClient(const RelayClientOptions& options, double now);
  ~RelayClient();
  RelayClient(const RelayClient&) = delete;
  RelayClient& operator=(const RelayClient&) = delete;

  // Handles at most kMaxEventsPerPoll link events and the timers; waits at most `wait_ms` for
  // the first event.
  void poll(double now, RelayListener& listener, std::uint32_t wait_ms = 0);
  // After on_relay_ready: enter the room (within 3 s: the relay lets go of connections that do
  // not enter; the client then reconnects and says on_relay_ready again). room_params is kept by
  // the relay as the room's if the room is empty (the first member's), else the room's own are
  // returned in on_entered. Sizes above kRoomParamsMax / kAnnounceMax are not sent (false).
  bool enter(std::span<const std::uint8_t> room_params, std::span<const std::uint8_t> announce);
  // kAllMembers: all others. False when not in a room, the payload is empty or above
  // kRelayPayloadMax, or the link refuses it. Tracking is flushed at once.
  bool send(MemberId to, Channel channel, std::span<const std::uint8_t> payload);
  bool in_room() const { return in_room_; }
  MemberId self() const { return self_; }
  bool connected() const { return welcomed_; }  // the relay's welcome was accepted
  bool stopped() const { return stopped_; }     // a final refusal, or close()
  std::uint16_t local_port() const;
  // ENet's round-trip estimate to the relay in ms (0 while not connected).
  std::uint32_t round_trip_ms() const;
  const RelayClientStats& stats() const { return stats_; }
  const DropCounters& drops() const { return drop_log_.counters(); }
  // Leave politely, flush (≤ 0.5 s). The client stays stopped.
  void close(double now);

  static constexpr std::size_t kMaxEventsPerPoll = 256;

 private:
  void attempt(double now);
  void on_event(const LinkEvent& e, double now, RelayListener& listener);
  void on_packet(Channel channel, std::span<const std::byte> bytes, double now,
                 RelayListener& listener);
  void lost(double now, RelayListener& listener, const char* why);
  void stop(RelayRefusal why, double now, RelayListener& listener);
  void schedule(double now);
  spdlog::logger& log() const;
  bool send_reliable(std::span<const std::byte> packet);

  RelayClientOptions options_;
  std::unique_ptr<EnetLink> link_;
  DropLog drop_log_;
  LineBudget warn_budget_;
  RelayClientStats stats_;
  PeerId peer_ = kNoPeer;
  bool connected_ = false;  // the transport is up
  bool welcomed_ = false;
  bool entering_ = false;
  bool in_room_ = false;
  bool stopped_ = false;
  MemberId self_ = kNoMember;
  double last_heard_ = 0.0;
  double deadline_ = 0.0;      // connect/welcome deadline
  double next_attempt_ = 0.0;  // when not connected
  double next_keepalive_ = 0.0;
  double backoff_ = kRelayReconnectMin;
  std::vector<std::byte> tx_;  // one forward, preallocated
};

}  // namespace deixis::net
