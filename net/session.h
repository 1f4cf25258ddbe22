#pragma once
// One site's connection to the other (DESIGN §9; docs/protocol.md, "State machine"), over any
// Link (ENet, or the simulated network), on the caller's clock:
//
//   kWaiting ─connect─▶ kConnecting ─▶ kHandshake ─welcome/join/accept─▶ kHello ─hellos─▶
//   kStreaming
//       ▲                   │              │                               │               │
//       └─── retry (joiner, backoff) ◀─────┴── time-out, bye, transport lost ┴───────────────┘
//   kRefused: the peer refused us, or we it, for a reason retrying cannot fix (wrong passphrase,
//   passphrase on one side only, another protocol version). kIdle: not started, or closed.
//
// A host listens and serves one joiner at a time; after a connection ends it listens again. A
// joiner reconnects by itself with a backoff. Heartbeats go every heartbeat_interval; a peer not
// heard for heartbeat_timeout has timed out (status().last_end says so). Tracking received while
// streaming goes through the jitter buffer (next_frame); when the stream stops or the connection
// ends, next_frame says kNoStream, so the remote avatar is hidden, never frozen.
//
// With a passphrase, every packet after the handshake is sealed (sealing.h) and anything that is
// not is counted and dropped; a peer that cannot prove the passphrase is refused before it sees a
// hello, a target map or a tracking frame.
//
// Nothing received is trusted: each packet is decoded from its bytes with bounds and range checks,
// and a bad one is counted per reason and logged at a limited rate (drop_log.h). Streaming
// (send_tracking, service, next_frame) allocates nothing in the session itself.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "net/drop_log.h"
#include "net/jitter_buffer.h"
#include "net/link.h"
#include "net/messages.h"
#include "net/sealing.h"
#include "net/tracking_codec.h"

namespace spdlog {
class logger;
}

namespace deixis::net {

enum class Role : std::uint8_t { kHost, kJoiner };

enum class SessionState : std::uint8_t {
  kIdle,
  kWaiting,     // host: listening; joiner: waiting for the next attempt
  kConnecting,  // joiner: the transport is connecting
  kHandshake,   // welcome, join, accept (authentication when there is a passphrase)
  kHello,       // authenticated; waiting for the peer's hello
  kStreaming,   // hellos exchanged: tracking flows both ways
  kRefused,     // terminal: see status().last_bye
};
std::string_view state_name(SessionState state);

// Why the last connection (or attempt) ended.
enum class EndCause : std::uint8_t {
  kNone,
  kConnectFailed,      // the attempt did not connect in time (or the host was busy)
  kHandshakeTimedOut,  // connected, but the handshake did not finish in time
  kTimedOut,           // the peer fell silent for heartbeat_timeout
  kByeFromPeer,        // the peer said bye (status().last_bye: why)
  kRefusedPeer,        // we refused the peer (status().last_bye: why)
  kTransportLost,      // the transport reported the peer gone without a bye
  kClosed,             // close() was called
};
std::string_view end_cause_name(EndCause cause);

struct SessionConfig {
  Role role = Role::kJoiner;
  Hello hello;                      // ours: site, avatar, body calibration
  TargetMap target_map;             // ours
  std::string passphrase;           // empty: an open session
  KdfCost kdf;                      // host: the cost of deriving the key (the joiner follows it)
  double heartbeat_interval = 0.5;  // s
  double heartbeat_timeout = 3.0;   // s of silence before the peer counts as gone
  double handshake_timeout = 5.0;   // s from connecting to streaming
  double connect_timeout = 3.0;     // s per attempt (joiner)
  double reconnect_min = 0.5;       // s before the first retry; doubles per failed attempt
  double reconnect_max = 4.0;       // s
  JitterConfig jitter;
  std::shared_ptr<spdlog::logger> logger;  // null: spdlog's default logger
};

struct PeerStatus {
  SessionState state = SessionState::kIdle;
  EndCause last_end = EndCause::kNone;
  ByeReason last_bye = ByeReason::kLeaving;  // with kByeFromPeer, kRefusedPeer, kRefused
  double last_heard = 0.0;                   // our clock; the last packet accepted from the peer
  double next_attempt = 0.0;                 // joiner in kWaiting: when it tries again
  std::uint32_t round_trip_ms = 0;
  std::uint64_t attempts = 0;       // connection attempts (joiner) or connections (host)
  std::uint64_t streams = 0;        // connections that reached kStreaming
  std::uint64_t timeouts = 0;       // heartbeat time-outs
  std::uint64_t auth_failures = 0;  // proofs that did not verify
};

struct SessionStats {
  std::uint64_t packets_sent = 0;
  std::uint64_t bytes_sent = 0;  // packet bytes handed to the link (ENet adds its headers)
  std::uint64_t send_failures = 0;
  std::uint64_t packets_received = 0;
  std::uint64_t bytes_received = 0;
  std::uint64_t tracking_sent = 0;
  std::uint64_t tracking_received = 0;  // decoded and handed to the jitter buffer
  std::uint64_t parts_not_sent = 0;     // tracked parts the encoder could not represent
  std::uint64_t target_maps_received = 0;
};

class Session {
 public:
  // Throws deixis::Error when our hello or target map breaks a wire rule, or when the passphrase
  // key cannot be derived (a configuration error, reported before anything is sent).
  Session(Link& link, SessionConfig config);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Host: start listening. Joiner: make the first attempt.
  void start(double now);
  // Handles every link event and timer; waits at most `wait_ms` for the first event.
  void service(double now, std::uint32_t wait_ms = 0);
  // Sends a tracking frame (only while streaming; false otherwise or when the link refuses).
  bool send_tracking(const TrackingFrame& frame);
  // The remote person's next tracking result (jitter_buffer.h): call until kPending or kNoStream.
  Playout next_frame(double now);
  // Replaces our target map and sends it when connected. Throws deixis::Error if it breaks a
  // wire rule.
  void set_target_map(const TargetMap& map);
  // Says bye and closes; the session stays kIdle until start() again.
  void close(double now);

  SessionState state() const { return status_.state; }
  const PeerStatus& status() const { return status_; }
  double silence(double now) const { return now - status_.last_heard; }
  const Hello* remote_hello() const { return remote_hello_ ? &*remote_hello_ : nullptr; }
  const TargetMap* remote_target_map() const { return remote_map_ ? &*remote_map_ : nullptr; }
  const SessionStats& stats() const { return stats_; }
  const DropCounters& drops() const { return drop_log_.counters(); }
  const DropLog& drop_log() const { return drop_log_; }
  const JitterStats& jitter() const { return jitter_.stats(); }
  const SessionConfig& config() const { return config_; }
  bool sealed() const { return sealer_.has_value(); }  // this connection's packets are sealed

 private:
  bool has_passphrase() const { return !config_.passphrase.empty(); }
  bool connected() const;
  spdlog::logger& log() const;

  // Link events.
  void on_connected(double now);
  void on_disconnected(std::uint32_t code, double now);
  void on_packet(Channel channel, std::span<const std::byte> bytes, double now);
  void dispatch(Channel channel, std::span<const std::byte> packet, double now);
  void drop(Channel channel, std::span<const std::byte> packet, WireResult why, double now);

  // Messages.
  void on_welcome(const Welcome& m, double now);
  void on_join(const Join& m, double now);
  void on_accept(const Accept& m, double now);
  void on_hello(Hello&& m);
  void on_bye(const Bye& m, double now);
  void on_tracking(Channel channel, std::span<const std::byte> packet, double now);

  // Transitions.
  void begin_connection(double now);
  void authenticated(const Key& master);
  void enter_hello(double now);
  void refuse(ByeReason reason, double now);  // we refuse the peer
  void end_connection(EndCause cause, double now);
  void schedule_attempt(double now);
  void attempt(double now);
  void timers(double now);

  // Sending.
  bool send_reliable(std::span<const std::byte> packet);
  bool send_bye(ByeReason reason);
  void send_hello_and_map();

  Link& link_;
  SessionConfig config_;
  DropLog drop_log_;
  JitterBuffer jitter_;
  PeerStatus status_;
  SessionStats stats_;

  // Ours, encoded once (and on set_target_map).
  std::vector<std::byte> hello_bytes_;
  std::vector<std::byte> map_bytes_;
  // Host: the session's salt and master key; joiner: the key for the last salt it was given.
  Salt salt_{};
  KdfCost key_cost_{0, 0};
  std::optional<Key> master_key_;

  // This connection.
  Challenge host_challenge_{};
  Challenge joiner_challenge_{};
  bool welcome_seen_ = false;
  bool join_seen_ = false;
  std::optional<PacketSealer> sealer_;
  std::optional<PacketOpener> opener_;
  double deadline_ = 0.0;  // connect or handshake deadline
  double next_heartbeat_ = 0.0;
  std::uint32_t heartbeats_sent_ = 0;
  std::uint32_t tracking_sequence_ = 0;
  double reconnect_delay_ = 0.0;
  std::optional<Hello> remote_hello_;
  std::optional<TargetMap> remote_map_;

  // Preallocated buffers: streaming touches nothing else.
  std::array<std::byte, kTrackingBytes> tracking_tx_{};
  std::vector<std::byte> sealed_tx_;
  std::vector<std::byte> plain_rx_;
  std::vector<std::byte> scratch_;  // handshake messages
  TrackingMessage tracking_rx_;
};

}  // namespace deixis::net
