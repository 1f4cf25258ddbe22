#pragma once
// One site's connection to the other (docs/protocol.md, "State machine"), over any
// Link (ENet, or the simulated network), on the caller's clock:
//
//   kWaiting ─connect─▶ kConnecting ─▶ kHandshake ─welcome/join/accept─▶ kHello ─hellos─▶
//   kStreaming
//       ▲                   │              │                               │               │
//       └─── retry (joiner, backoff) ◀─────┴── time-out, bye, transport lost ┴───────────────┘
//   kRefused: the peer refused us, or we it, for a reason retrying cannot fix (wrong passphrase,
//   passphrase on one side only, another protocol version). kIdle: not started, or closed.
//
// A host listens and serves one joiner at a time: the first that *completes* the handshake, not
// the first that connected. Strangers still in their handshake wait in a bounded table (a short
// deadline each, a small budget per network address, the oldest let go when it is full), so that
// silent connections never keep the rightful joiner out; an address whose proofs fail is held back
// for longer and longer. After a connection ends the host listens again. A joiner reconnects by
// itself with a backoff. Heartbeats go every heartbeat_interval; a peer not
// heard for heartbeat_timeout has timed out (status().last_end says so). Tracking received while
// streaming goes through the jitter buffer (next_frame); when the stream stops or the connection
// ends, next_frame says kNoStream, so the remote avatar is hidden, never frozen.
//
// With a passphrase, every packet after the handshake is sealed (sealing.h) and anything that is
// not is counted and dropped; a peer that cannot prove the passphrase is refused before it sees a
// hello, a target map or a tracking frame, or learns whether a call is in progress. Argon2id runs
// off the caller's thread (key_derivation.h): the session stays in its handshake until it is done.
//
// Work per service() call is bounded (max_events_per_service), and the peer has a packet and byte
// budget per second: one that floods is cut off with a logged reason (docs/security.md).
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

#include "net/avatar_transfer.h"
#include "net/drop_log.h"
#include "net/jitter_buffer.h"
#include "net/key_derivation.h"
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
  kFlooded,            // the peer sent more than its budget and was cut off
};
std::string_view end_cause_name(EndCause cause);

// What one peer may send per second (docs/security.md): a token bucket of `burst_seconds` worth.
// Tracking at 30 Hz, heartbeats and an occasional target map use about a third of the packets; an
// avatar file in transfer (net/avatar_transfer.h, paced at 128 KiB a second) half of the bytes.
struct PeerBudget {
  double packets_per_second = 120.0;
  double bytes_per_second = 256.0 * 1024.0;
  double burst_seconds = 2.0;
};

struct SessionConfig {
  Role role = Role::kJoiner;
  Hello hello;                        // ours: site, avatar, body calibration
  TargetMap target_map;               // ours
  std::string passphrase;             // empty: an open session
  KdfCost kdf;                        // host: the cost of deriving the key (the joiner follows it)
  KdfCost min_kdf = kInteractiveKdf;  // joiner: the weakest welcome cost it accepts
  // Derive the passphrase key on the calling thread: for simulated-clock tests and fuzzing only.
  bool derive_on_this_thread = false;
  double heartbeat_interval = 0.5;  // s
  double heartbeat_timeout = 3.0;   // s of silence before the peer counts as gone
  double handshake_timeout = 5.0;   // s from connecting to streaming
  double connect_timeout = 3.0;     // s per attempt (joiner)
  double reconnect_min = 0.5;       // s before the first retry; doubles per failed attempt
  double reconnect_max = 4.0;       // s
  // Host: strangers in their handshake (docs/protocol.md §6).
  double pending_timeout = 3.0;             // s from connecting to a verified join
  std::size_t max_pending = 32;             // at once (the link holds twice as many peers)
  std::size_t max_pending_per_address = 4;  // at once from one network address
  std::size_t free_failures = 3;            // failed proofs per address before any backoff
  double max_backoff = 60.0;                // s an address waits after repeated failed proofs
  std::size_t rotate_salt_after = 8;        // failed proofs before the host draws a new salt
  std::size_t max_events_per_service = 64;  // link events one service() call handles at most
  PeerBudget budget;
  JitterConfig jitter;
  std::shared_ptr<spdlog::logger> logger;  // null: spdlog's default logger
  // The avatar file our person chose, sent to a peer that asks for it (net/avatar_transfer.h);
  // the session names it in our hello by its hash. Null: the hello names none.
  std::shared_ptr<const std::vector<std::byte>> avatar_file;
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
  std::uint64_t hellos = 0;         // hellos accepted; more than one in a stream: a new one
                                    // (a recalibration, docs/protocol.md §4.4)
  std::uint64_t timeouts = 0;       // heartbeat time-outs
  std::uint64_t auth_failures = 0;  // proofs that did not verify
};

// Host: what became of the strangers that connected (docs/security.md).
struct StrangerStats {
  std::uint64_t connected = 0;    // connections accepted into the handshake table
  std::uint64_t over_budget = 0;  // turned away at once: their address had too many pending
  std::uint64_t evicted = 0;      // let go to make room (the table was full)
  std::uint64_t timed_out = 0;    // no verified join within pending_timeout
  std::uint64_t held_back = 0;    // joins refused while their address was backing off
  std::uint64_t busy = 0;         // proved the passphrase (or open) while we served another
  std::uint64_t chatty = 0;       // sent more than a handshake needs
  std::uint64_t salts_rotated = 0;
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
  std::uint64_t floods_cut = 0;                // peers cut off for exceeding their budget
  std::uint64_t service_bounded = 0;           // service() calls that left events for the next one
  std::uint64_t avatar_requests_received = 0;  // for our file
  std::uint64_t avatar_chunks_sent = 0;
  std::uint64_t avatar_chunks_received = 0;  // taken by the download
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
  // Handles link events (at most max_events_per_service) and timers; waits at most `wait_ms`
  // for the first event.
  void service(double now, std::uint32_t wait_ms = 0);
  // Sends a tracking frame (only while streaming; false otherwise or when the link refuses).
  bool send_tracking(const TrackingFrame& frame);
  // The remote person's next tracking result (jitter_buffer.h): call until kPending or kNoStream.
  Playout next_frame(double now);
  // Replaces our hello (a new calibration of the user) and sends it when past the handshake; the
  // site's name and the avatar file we send stay. Throws deixis::Error if it breaks a wire rule.
  void set_hello(const Hello& hello);
  // Replaces our target map and sends it when connected. Throws deixis::Error if it breaks a
  // wire rule.
  void set_target_map(const TargetMap& map);
  // Says bye and closes; the session stays kIdle until start() again.
  void close(double now);

  SessionState state() const { return status_.state; }
  PeerId peer() const { return peer_; }  // the connection served (or attempted); kNoPeer: none
  const PeerStatus& status() const { return status_; }
  double silence(double now) const { return now - status_.last_heard; }
  const Hello* remote_hello() const { return remote_hello_ ? &*remote_hello_ : nullptr; }
  const TargetMap* remote_target_map() const { return remote_map_ ? &*remote_map_ : nullptr; }
  const SessionStats& stats() const { return stats_; }
  const StrangerStats& strangers() const { return strangers_; }
  std::size_t pending() const { return pending_.size(); }  // host: strangers in their handshake
  // The passphrase key is being derived (the handshake waits for it).
  bool deriving_key() const { return derivation_.started(); }
  const DropCounters& drops() const { return drop_log_.counters(); }
  const DropLog& drop_log() const { return drop_log_; }
  const JitterStats& jitter() const { return jitter_.stats(); }
  const SessionConfig& config() const { return config_; }
  bool sealed() const { return sealer_.has_value(); }  // this connection's packets are sealed

  // The avatar file the peer's hello names (nullopt: none, the receiving site chooses).
  std::optional<AvatarHash> remote_avatar_hash() const;
  // Asks the peer for that file (a site whose cache lacks it); false when there is none to ask
  // for or we are not past the hello exchange. The download then fills avatar_download().
  bool request_avatar();
  const AvatarReceiver& avatar_download() const { return avatar_rx_; }

 private:
  // Host: a stranger in its handshake, until its join is verified (then it is served or told
  // busy) or it is let go.
  struct Pending {
    PeerId peer = kNoPeer;
    std::uint32_t address = 0;
    double since = 0.0;
    double deadline = 0.0;
    Welcome welcome;  // what we sent it
    ExchangeKeyPair keys;
    std::optional<Join> join;  // its join, waiting for our key
    int packets = 0;
  };
  // Host: failed proofs per network address, for the backoff.
  struct AddressRecord {
    std::uint32_t address = 0;
    std::size_t failures = 0;
    double last_failure = -1e300;
    double blocked_until = 0.0;
  };
  // Host: the passphrase key for one salt.
  struct HostKey {
    Salt salt{};
    KdfCost cost{0, 0};
    std::optional<Key> master;
  };
  struct Bucket {
    double packets = 0.0;
    double bytes = 0.0;
    double last = 0.0;
  };

  bool has_passphrase() const { return !config_.passphrase.empty(); }
  bool is_host() const { return config_.role == Role::kHost; }
  bool connected() const;
  bool serving() const;  // host: a peer past its handshake
  spdlog::logger& log() const;
  // The peer's address, kept from when its connection began (the link forgets a peer it lost).
  std::string_view peer_name() const { return peer_label_.data(); }

  // Link events.
  void on_event(const LinkEvent& e, double now);
  void on_connected(PeerId peer, double now);
  void on_disconnected(std::uint32_t code, double now);
  void on_packet(Channel channel, std::span<const std::byte> bytes, double now);
  void dispatch(Channel channel, std::span<const std::byte> packet, double now);
  // One message kind through its bounded decoder to `handle`, if this state accepts it (else
  // dropped as unexpected); a wrong protocol version in the handshake is refused with a reason.
  template <class Message, class Handle>
  void accept(Channel channel, std::span<const std::byte> packet, bool allowed, double now,
              Handle&& handle);
  void drop(Channel channel, std::span<const std::byte> packet, WireResult why, double now);
  bool within_budget(std::size_t bytes, double now);

  // Host: strangers.
  void on_stranger(PeerId peer, double now);
  void on_stranger_packet(Pending& p, Channel channel, std::span<const std::byte> bytes,
                          double now);
  void verify_join(Pending& p, double now);
  void serve(Pending& p, const std::optional<Key>& prk, const std::string& joiner_site, double now);
  void send_plain_bye(PeerId peer, ByeReason reason);
  void let_go(PeerId peer, ByeReason reason);
  void remove_pending(PeerId peer);
  Pending* find_pending(PeerId peer);
  std::size_t pending_from(std::uint32_t address) const;
  void evict_one(double now);
  AddressRecord& record_of(std::uint32_t address, double now);
  bool held_back(std::uint32_t address, double now) const;
  void failed_proof(std::uint32_t address, double now);
  const HostKey* host_key_for(const Salt& salt) const;
  void host_key_timers();
  void pending_timers(double now);

  // Messages (the served peer, or the joiner's host).
  void on_welcome(const Welcome& m, double now);
  void send_join(double now);
  void on_accept(const Accept& m, double now);
  void on_hello(Hello&& m, double now);
  void on_bye(const Bye& m, double now);
  void on_tracking(Channel channel, std::span<const std::byte> packet, double now);
  void on_avatar_request(const AvatarRequest& m, Channel channel, std::span<const std::byte> packet,
                         double now);
  void on_avatar_data(const AvatarData& m, Channel channel, std::span<const std::byte> packet,
                      double now);
  void send_avatar_chunks(double now);

  // Transitions.
  void label_peer(PeerId peer);
  void begin_connection(PeerId peer, double now);
  void authenticated(const Key& prk, std::string_view joiner_site, std::string_view host_site);
  void enter_hello(double now);
  void refuse(ByeReason reason, double now);  // we refuse the peer
  void cut_off(double now);                   // the peer flooded
  void end_connection(EndCause cause, double now);
  void schedule_attempt(double now);
  void attempt(double now);
  void timers(double now);
  void warn_limited(double now, std::string_view what);

  // Sending.
  bool send_to(PeerId peer, std::span<const std::byte> packet);  // plain, reliable
  bool send_reliable(std::span<const std::byte> packet);
  bool send_bye(ByeReason reason);
  void send_hello_and_map();

  Link& link_;
  SessionConfig config_;
  DropLog drop_log_;
  LineBudget warn_budget_;
  JitterBuffer jitter_;
  PeerStatus status_;
  SessionStats stats_;
  StrangerStats strangers_;

  // Ours, encoded once (and on set_target_map).
  std::vector<std::byte> hello_bytes_;
  std::vector<std::byte> map_bytes_;
  KeyDerivation derivation_;
  // Host: the key for the salt in our welcomes, and the one before it (strangers welcomed before
  // a rotation); joiner: the key for the last salt and cost it was given.
  HostKey key_;
  HostKey previous_key_;
  std::size_t failures_since_rotation_ = 0;
  std::vector<Pending> pending_;  // host; capacity max_pending, never more
  std::array<AddressRecord, 64> addresses_{};

  // This connection (the served peer, or the joiner's attempt).
  PeerId peer_ = kNoPeer;
  std::array<char, 64> peer_label_{};
  Welcome welcome_;                               // joiner: the host's welcome
  Join welcome_join_;                             // joiner: our answer to it
  std::optional<ExchangeKeyPair> exchange_keys_;  // joiner: ours
  std::string peer_site_;  // the site name the peer proved (passphrase sessions)
  bool welcome_seen_ = false;
  bool join_sent_ = false;
  std::optional<PacketSealer> sealer_;
  std::optional<PacketOpener> opener_;
  Bucket budget_;
  double deadline_ = 0.0;  // connect or handshake deadline
  double next_heartbeat_ = 0.0;
  std::uint32_t heartbeats_sent_ = 0;
  std::uint32_t tracking_sequence_ = 0;
  double reconnect_delay_ = 0.0;
  std::optional<Hello> remote_hello_;
  std::optional<TargetMap> remote_map_;
  AvatarSender avatar_tx_;    // our file, if we have one
  AvatarReceiver avatar_rx_;  // the peer's, when requested

  // Preallocated buffers: streaming touches nothing else.
  std::array<std::byte, kTrackingBytes> tracking_tx_{};
  std::vector<std::byte> avatar_chunk_tx_;  // one avatar-data packet
  std::vector<std::byte> padded_tx_;
  std::vector<std::byte> sealed_tx_;
  std::vector<std::byte> plain_rx_;
  std::vector<std::byte> scratch_;  // handshake messages
  TrackingMessage tracking_rx_;
};

}  // namespace deixis::net
