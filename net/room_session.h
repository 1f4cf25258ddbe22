#pragma once
// One site's membership of a room of several people behind a relay (docs/rooms-protocol.md), on
// the caller's clock. The relay forwards payloads and says who entered and left; everything the
// members say to each other is this class's business, and with a passphrase it is sealed end to
// end: the relay and anyone who does not know the passphrase see sizes and timing only.
//
//   on_relay_ready ─enter(params, fresh announce)─▶ on_entered ─▶ in the room
//   per member:  announced ──(the later of the two proves first: key message)──▶ the earlier
//                member opens it, answers with its own ──▶ verified both ways ─▶ hello, target
//                map, tracking, heartbeats ─▶ left (relay), bye, timed out, or flooded
//
// A member whose key message does not open (another passphrase, a relay that swapped senders or
// changed the announces) is shown to no one, never receives our key or anything sealed with it,
// and its packets are counted and dropped. Until every member in the room is verified, what we
// seal is sent to the verified ones one by one instead of to all, so an unverified member gets
// nothing of ours at all. In an open room (no passphrase) nothing is sealed; a member with a
// passphrase refuses an open room and one without refuses a sealed room, clearly (refusal()).
//
// Transport: the RelayListener callbacks come from RelayClient::poll (or the tests' in-process
// relay, tests/net/room_fixture.h); sends go through a RoomTransport, which RelayClient satisfies
// through RelayTransport below. The callbacks carry no clock: call poll(now) first in each tick,
// then the client's poll(now, room); the callbacks use the time of the last poll().
//
// The passphrase key is derived off the caller's thread (key_derivation.h); key messages that
// arrive meanwhile wait (one per member). Work per packet is bounded; each member has a packet
// and byte budget (PeerBudget), and one that floods is no longer listened to. Once the room is
// stable (no one entering or leaving) poll, send_tracking, the callbacks and next_playout
// allocate nothing.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "net/avatar_transfer.h"
#include "net/drop_log.h"
#include "net/jitter_buffer.h"
#include "net/key_derivation.h"
#include "net/messages.h"
#include "net/relay_client.h"
#include "net/room_keys.h"
#include "net/session.h"
#include "net/tracking_codec.h"

namespace spdlog {
class logger;
}

namespace deixis::net {

// What a RoomSession needs of the relay connection.
class RoomTransport {
 public:
  virtual ~RoomTransport() = default;
  virtual bool enter(std::span<const std::uint8_t> room_params,
                     std::span<const std::uint8_t> announce) = 0;
  virtual bool send(MemberId to, Channel channel, std::span<const std::uint8_t> payload) = 0;
};

// RelayClient as a RoomTransport.
class RelayTransport final : public RoomTransport {
 public:
  explicit RelayTransport(RelayClient& client) : client_(client) {}
  bool enter(std::span<const std::uint8_t> room_params,
             std::span<const std::uint8_t> announce) override {
    return client_.enter(room_params, announce);
  }
  bool send(MemberId to, Channel channel, std::span<const std::uint8_t> payload) override {
    return client_.send(to, channel, payload);
  }

 private:
  RelayClient& client_;
};

enum class RoomState : std::uint8_t {
  kWaiting,   // no relay yet, or it was lost: waiting for on_relay_ready
  kEntering,  // enter() sent, waiting for on_entered
  kInRoom,    // in the room: people appear as they prove themselves and say hello
  kRefused,   // for good: refusal() says why
};
std::string_view room_state_name(RoomState state);

enum class RoomRefusal : std::uint8_t {
  kNone,
  kPassphraseRequired,    // the room is sealed; this site has no passphrase
  kPassphraseUnexpected,  // the room is open; this site has a passphrase
  kWeakKeyCost,           // the room's Argon2id cost is below this site's floor
  kBadRoomParams,         // the relay handed over room params that do not decode
  kKeyFailed,             // Argon2id failed (out of memory)
  kRelay,                 // the relay refused us for good (room full, version, not a relay)
};

enum class RoomEventKind : std::uint8_t {
  kArrived,           // a verified person's first hello: show them
  kHelloChanged,      // they said hello again, with something else
  kTargetMapChanged,  // their target map (first or new)
  kLeft,              // gone (why: LeftBecause): hide them, free their spot
  kAvatarFile,        // the avatar file asked for is complete or abandoned (avatar_download)
};
enum class LeftBecause : std::uint8_t { kLeft, kBye, kTimedOut, kFlooded, kRelayLost, kClosed };
std::string_view left_because_name(LeftBecause why);

struct RoomEvent {
  RoomEventKind kind = RoomEventKind::kArrived;
  MemberId person = kNoMember;
  LeftBecause why = LeftBecause::kLeft;  // kLeft only
};

struct RoomConfig {
  Hello hello;                        // ours: site, avatar, body calibration
  TargetMap target_map;               // ours
  std::string passphrase;             // empty: an open room
  KdfCost kdf = kInteractiveKdf;      // the cost we propose if we are the room's first member
  KdfCost min_kdf = kInteractiveKdf;  // the weakest room cost we accept
  // Derive the passphrase key on the calling thread: for simulated-clock tests only.
  bool derive_on_this_thread = false;
  double heartbeat_interval = 0.5;  // s
  double heartbeat_timeout = 3.0;   // s without an accepted packet: the person timed out
  std::size_t max_members = 16;     // members held at once, verified or not (the relay's default
                                    // room is 8); more are ignored
  PeerBudget budget;                // per member
  JitterConfig jitter;              // per person
  std::shared_ptr<spdlog::logger> logger;  // null: spdlog's default logger
  // The avatar file our person chose, sent to each member that asks for it
  // (net/avatar_transfer.h); our hello then names it by its hash. Null: none.
  std::shared_ptr<const std::vector<std::byte>> avatar_file;
};

struct RoomStats {
  std::uint64_t entries = 0;  // rooms entered (again after each relay loss)
  std::uint64_t key_messages_sent = 0;
  std::uint64_t verified = 0;       // members whose key message opened
  std::uint64_t auth_failures = 0;  // members whose key message did not open
  std::uint64_t people_arrived = 0;
  std::uint64_t people_left = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t floods = 0;         // members no longer listened to for flooding
  std::uint64_t over_capacity = 0;  // members ignored: max_members were held already
  std::uint64_t tracking_sent = 0;  // frames sealed (once) and sent
  // Frames decoded from everyone, people who have left included (PersonStats holds one
  // person's only while they are here).
  std::uint64_t tracking_received = 0;
  std::uint64_t parts_not_sent = 0;  // tracked parts the encoder could not represent
  std::uint64_t sends = 0;           // payloads handed to the transport
  std::uint64_t send_failures = 0;
  std::uint64_t events_coalesced = 0;          // events already waiting to be taken
  std::uint64_t avatar_requests_received = 0;  // for our file
  std::uint64_t avatar_chunks_sent = 0;
};

struct PersonStats {
  std::uint64_t tracking_received = 0;  // decoded and handed to the jitter buffer
  std::uint64_t hellos = 0;
  std::uint64_t target_maps = 0;
  std::uint64_t heartbeats = 0;
  std::uint64_t avatar_chunks_received = 0;  // taken by the download
  DropCounters drops;                        // this member's packets dropped, by reason
};

class RoomSession final : public RelayListener {
 public:
  // Throws deixis::Error when our hello or target map breaks a wire rule, the proposed cost is
  // outside docs/protocol.md §4.1's bounds, or max_members is 0.
  RoomSession(RoomTransport& transport, RoomConfig config);
  ~RoomSession() override;
  RoomSession(const RoomSession&) = delete;
  RoomSession& operator=(const RoomSession&) = delete;

  // Timers (the key derivation, proofs waiting for it, heartbeats, time-outs); sets the clock the
  // next callbacks use.
  void poll(double now);
  // Seals our frame once (stamped `sampled`) and sends it to every verified person; false when
  // there is no one to send to or the transport refused it.
  bool send_tracking(const TrackingFrame& frame, double sampled);
  // Replaces our hello (another avatar, a new calibration) and sends it to everyone verified.
  // Throws deixis::Error if it breaks a wire rule or names another site (our key messages carry
  // the site name, and the others hold us to it).
  void set_hello(const Hello& hello);
  // Replaces our target map and sends it to everyone verified. Throws deixis::Error if it breaks
  // a wire rule.
  void set_target_map(const TargetMap& map);
  // Says bye to everyone verified; the room is forgotten (people left: kClosed). The caller then
  // closes the relay client.
  void leave(double now);

  // Events for the site runtime, oldest first; false when there is none.
  bool next_event(RoomEvent& out);
  // Verified people who said hello, in order of arrival.
  std::span<const MemberId> people() const { return std::span(people_).first(people_count_); }
  const Hello* hello(MemberId person) const;
  const TargetMap* target_map(MemberId person) const;  // null until their first map
  // The person's next tracking result (jitter_buffer.h); kNoStream for anyone not in people().
  Playout next_playout(MemberId person, double now);
  const JitterStats* jitter(MemberId person) const;
  // The avatar file the person's hello names (nullopt: none, the receiving site chooses).
  std::optional<AvatarHash> avatar_hash(MemberId person) const;
  // Asks the person for that file (the site's cache lacks it): false when there is none to ask
  // for. The download fills avatar_download(person); kAvatarFile says when it is done.
  bool request_avatar(MemberId person);
  const AvatarReceiver* avatar_download(MemberId person) const;
  const PersonStats* person_stats(MemberId person) const;

  RoomState state() const { return state_; }
  RoomRefusal refusal() const { return refusal_; }
  const std::string& refusal_text() const { return refusal_text_; }  // words for the user
  MemberId self() const { return self_; }
  bool sealed() const { return has_passphrase(); }
  bool deriving_key() const { return derivation_.started(); }
  std::size_t members() const;     // held: verified or not
  std::size_t unverified() const;  // held, not (yet) verified
  const RoomStats& stats() const { return stats_; }
  const DropCounters& drops() const { return drop_log_.counters(); }
  const DropLog& drop_log() const { return drop_log_; }
  const RoomConfig& config() const { return config_; }

  // RelayListener.
  void on_relay_ready() override;
  void on_entered(MemberId self, std::span<const std::uint8_t> room_params,
                  std::span<const RoomMember> already_there) override;
  void on_member_joined(const RoomMember& member) override;
  void on_member_left(MemberId id) override;
  void on_payload(MemberId from, Channel channel, std::span<const std::uint8_t> payload) override;
  void on_refused(RelayRefusal why) override;
  void on_relay_lost() override;

 private:
  struct Member;
  enum class Stage : std::uint8_t;

  bool has_passphrase() const { return !config_.passphrase.empty(); }
  spdlog::logger& log() const;
  Member* find(MemberId id);
  const Member* find_person(MemberId id) const;  // verified and said hello

  void add_member(MemberId id, std::span<const std::uint8_t> announce, bool later);
  void prepare(Member& m);  // the pair's secret once the master key is there; proves if due
  void send_key_message(Member& m);
  void on_key_message(Member& m, std::span<const std::byte> packet);
  void verified(Member& m);
  void failed(Member& m, const char* why);
  void dispatch(Member& m, Channel channel, std::span<const std::byte> inner);
  void on_hello(Member& m, std::span<const std::byte> inner);
  void on_target_map(Member& m, std::span<const std::byte> inner);
  void on_tracking(Member& m, Channel channel, std::span<const std::byte> inner);
  void on_avatar_request(Member& m, std::span<const std::byte> inner);
  void on_avatar_data(Member& m, std::span<const std::byte> inner);
  void send_avatar_chunks(Member& m);
  void gone(Member& m, LeftBecause why);  // the person leaves the site; the slot may stay
  void release(Member& m);                // the slot is free again
  void forget_everyone(LeftBecause why);
  void drop(Member* m, MemberId from, Channel channel, std::span<const std::byte> packet,
            WireResult why);
  bool within_budget(Member& m, std::size_t bytes);
  void push_event(RoomEventKind kind, MemberId person, LeftBecause why = LeftBecause::kLeft);
  void refuse(RoomRefusal why, std::string text);
  void key_timers();

  // Sending: one sealed packet to every verified member (all at once when everyone is).
  bool send_to_verified(Channel channel, std::span<const std::byte> inner);
  bool send_to(MemberId to, Channel channel, std::span<const std::byte> inner);
  bool transport_send(MemberId to, Channel channel, std::span<const std::byte> packet);
  std::span<const std::byte> seal(Channel channel, std::span<const std::byte> inner);
  bool everyone_verified() const;

  RoomTransport& transport_;
  RoomConfig config_;
  DropLog drop_log_;
  LineBudget warn_budget_;
  RoomStats stats_;
  RoomState state_ = RoomState::kWaiting;
  RoomRefusal refusal_ = RoomRefusal::kNone;
  std::string refusal_text_;
  double now_ = 0.0;

  // Ours, encoded once (and on set_target_map).
  std::vector<std::byte> hello_bytes_;
  std::vector<std::byte> map_bytes_;
  RoomParams own_params_;                   // proposed if the room is empty
  AvatarSender avatar_tx_;                  // our file, if we have one
  std::vector<std::byte> avatar_chunk_tx_;  // one avatar-data packet

  // This entry.
  MemberId self_ = kNoMember;
  RoomParams room_params_;
  Entry entry_;
  Key sender_key_{};
  std::optional<RoomSealer> sealer_;
  std::uint32_t tracking_sequence_ = 0;
  std::uint32_t heartbeats_sent_ = 0;
  double next_heartbeat_ = 0.0;

  // The master key for one salt and cost, derived off this thread.
  KeyDerivation derivation_;
  std::optional<Key> master_;
  Salt master_salt_{};
  KdfCost master_cost_{0, 0};

  std::unique_ptr<Member[]> members_;  // max_members slots
  std::array<bool, 256> ignored_{};    // in the room, not held (max_members were held already)
  std::array<MemberId, 256> people_{};
  std::size_t people_count_ = 0;
  std::vector<RoomEvent> events_;  // capacity fixed at construction
  std::size_t events_read_ = 0;

  // Preallocated buffers: the per-tick path touches nothing else.
  std::array<std::byte, kTrackingBytes> tracking_tx_{};
  std::array<std::byte, kHeartbeatBytes> heartbeat_tx_{};
  std::vector<std::byte> sealed_tx_;
  std::vector<std::byte> plain_rx_;
  TrackingMessage tracking_rx_;
};

}  // namespace deixis::net
