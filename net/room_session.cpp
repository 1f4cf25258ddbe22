#include "net/room_session.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>
#include <cstdio>

#include "core/error.h"

namespace deixis::net {

std::string_view room_state_name(RoomState state) {
  switch (state) {
    case RoomState::kWaiting:
      return "waiting for the relay";
    case RoomState::kEntering:
      return "entering";
    case RoomState::kInRoom:
      return "in the room";
    case RoomState::kRefused:
      return "refused";
  }
  return "?";
}

std::string_view left_because_name(LeftBecause why) {
  switch (why) {
    case LeftBecause::kLeft:
      return "left the room";
    case LeftBecause::kBye:
      return "said bye";
    case LeftBecause::kTimedOut:
      return "timed out";
    case LeftBecause::kFlooded:
      return "flooded";
    case LeftBecause::kRelayLost:
      return "relay lost";
    case LeftBecause::kClosed:
      return "we left";
  }
  return "?";
}

enum class RoomSession::Stage : std::uint8_t {
  kFree,       // an unused slot
  kAnnounced,  // in the room, not verified: no key yet, or waiting for its key message
  kProved,     // we sent it our key message (it was there first) and wait for its answer
  kVerified,   // its key message opened (or the room is open): it hears us, we hear it
  kFailed,     // its key message did not open, or its announce is unusable: shown to no one
  kGone,       // was verified, then said bye, timed out or flooded: ignored until it leaves
};

struct RoomSession::Member {
  MemberId id = kNoMember;
  Stage stage = Stage::kFree;
  bool later = false;     // it entered after us: it proves first
  bool sent_key = false;  // our key message went to it
  Announce announce;
  Key transcript{};
  std::optional<Key> prk;
  bool key_waiting = false;  // its key message arrived before our master key
  std::array<std::byte, kKeyMessageBytes> key_message{};
  std::string site;  // the name its key message carried
  std::optional<RoomOpener> opener;
  std::optional<Hello> hello;
  std::optional<TargetMap> map;
  AvatarReceiver avatar_rx;  // its file, when asked for
  JitterBuffer jitter;
  double last_heard = 0.0;
  double budget_packets = 0.0;
  double budget_bytes = 0.0;
  double budget_last = 0.0;
  PersonStats stats;
  std::array<char, 16> label{};  // "member 12", for log lines

  ~Member() {
    if (prk) {
      wipe(*prk);
    }
  }
};

namespace {

constexpr std::size_t kSealedBufferBytes = kMaxPacketBytes + kSealOverheadBytes;

std::span<const std::byte> as_bytes(std::span<const std::uint8_t> s) {
  return std::as_bytes(s);
}
std::span<const std::uint8_t> as_u8(std::span<const std::byte> s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

bool is(std::uint8_t type, MessageType t) {
  return type == static_cast<std::uint8_t>(t);
}

std::string cost_text(const KdfCost& c) {
  return std::to_string(c.opslimit) + " passes, " +
         (c.memlimit_kib % 1024 == 0 ? std::to_string(c.memlimit_kib / 1024) + " MiB"
                                     : std::to_string(c.memlimit_kib) + " KiB");
}

}  // namespace

RoomSession::RoomSession(RoomTransport& transport, RoomConfig config)
    : transport_(transport),
      config_(std::move(config)),
      drop_log_(config_.logger),
      sealed_tx_(kSealedBufferBytes),
      plain_rx_(kMaxPacketBytes) {
  if (config_.avatar_file) {
    // Our hello names the file by its hash: a member that has it cached never asks for it.
    avatar_tx_ = AvatarSender(*config_.avatar_file, "room: our avatar file");
    config_.hello.avatar.model = avatar_tx_.model();
    avatar_chunk_tx_.resize(kAvatarDataHeaderBytes + kAvatarChunkMaxBytes);
  }
  if (WireResult e = encode(config_.hello, hello_bytes_); !e.ok()) {
    throw Error(wire_message("room: our hello", e));
  }
  if (WireResult e = encode(config_.target_map, map_bytes_); !e.ok()) {
    throw Error(wire_message("room: our target map", e));
  }
  if (!sodium_ready()) {
    throw Error("room: libsodium failed to initialise");
  }
  if (config_.max_members == 0 || config_.max_members > kLastMember) {
    throw Error("room: max_members must be 1-254");
  }
  if (has_passphrase()) {
    const KdfCost& c = config_.kdf;
    if (c.opslimit < kMinKdfOps || c.opslimit > kMaxKdfOps || c.memlimit_kib < kMinKdfMemKib ||
        c.memlimit_kib > kMaxKdfMemKib || !at_least(c, config_.min_kdf)) {
      throw Error("room: the passphrase key cost (" + cost_text(c) +
                  ") is outside what members accept");
    }
  }
  own_params_ = make_room_params(has_passphrase(), config_.kdf);
  members_ = std::make_unique<Member[]>(config_.max_members);
  // At most one waiting event per kind and person (push_event coalesces), plus the lefts of a
  // slot's earlier holders.
  events_.reserve(8 * config_.max_members + 8);
}

RoomSession::~RoomSession() {
  wipe(sender_key_);
  if (master_) {
    wipe(*master_);
  }
}

spdlog::logger& RoomSession::log() const {
  return config_.logger ? *config_.logger : *spdlog::default_logger_raw();
}

RoomSession::Member* RoomSession::find(MemberId id) {
  if (id == kNoMember || id == kAllMembers) {
    return nullptr;
  }
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    if (members_[i].stage != Stage::kFree && members_[i].id == id) {
      return &members_[i];
    }
  }
  return nullptr;
}

const RoomSession::Member* RoomSession::find_person(MemberId id) const {
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    const Member& m = members_[i];
    if (m.stage == Stage::kVerified && m.id == id && m.hello) {
      return &m;
    }
  }
  return nullptr;
}

std::size_t RoomSession::members() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    n += members_[i].stage != Stage::kFree ? 1 : 0;
  }
  return n;
}

std::size_t RoomSession::unverified() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    const Stage s = members_[i].stage;
    n += (s == Stage::kAnnounced || s == Stage::kProved || s == Stage::kFailed) ? 1 : 0;
  }
  return n;
}

// ---- the relay's side ----

void RoomSession::on_relay_ready() {
  if (state_ == RoomState::kRefused) {
    return;
  }
  forget_everyone(LeftBecause::kRelayLost);
  // Fresh per entry: the announce (challenge, X25519 pair) and our sender key, so every entry
  // has fresh pair secrets and a counter restarting at 0 is a safe nonce.
  entry_ = make_entry(has_passphrase() ? AuthMode::kPassphrase : AuthMode::kOpen);
  random_bytes(sender_key_);
  sealer_.reset();
  if (has_passphrase()) {
    sealer_.emplace(sender_key_);
  }
  tracking_sequence_ = 0;
  heartbeats_sent_ = 0;
  std::array<std::byte, kRoomParamsBytes> params{};
  std::array<std::byte, kAnnounceBytes> announce{};
  encode(own_params_, params);
  encode(entry_.announce, announce);
  state_ = RoomState::kEntering;
  if (!transport_.enter(as_u8(params), as_u8(announce))) {
    ++stats_.send_failures;
  }
}

void RoomSession::on_entered(MemberId self, std::span<const std::uint8_t> room_params,
                             std::span<const RoomMember> already_there) {
  if (state_ != RoomState::kEntering) {
    return;
  }
  RoomParams p;
  if (WireResult e = decode(as_bytes(room_params), p); !e.ok()) {
    return refuse(RoomRefusal::kBadRoomParams,
                  wire_message("the relay handed over room parameters that do not decode", e));
  }
  if (p.auth == AuthMode::kPassphrase && !has_passphrase()) {
    return refuse(RoomRefusal::kPassphraseRequired,
                  "the room is sealed with a passphrase and this site has none: give the room's "
                  "passphrase");
  }
  if (p.auth == AuthMode::kOpen && has_passphrase()) {
    return refuse(RoomRefusal::kPassphraseUnexpected,
                  "the room is open (no passphrase) and this site has one: its members would see "
                  "everything unsealed; leave the passphrase out to join an open room");
  }
  if (p.auth == AuthMode::kPassphrase && !at_least(p.kdf, config_.min_kdf)) {
    return refuse(RoomRefusal::kWeakKeyCost, "the room's key cost (" + cost_text(p.kdf) +
                                                 ") is below this site's floor (" +
                                                 cost_text(config_.min_kdf) + ")");
  }
  if (self < kFirstMember || self > kLastMember) {
    return refuse(RoomRefusal::kBadRoomParams,
                  "the relay gave this site member id " + std::to_string(self) + " (not 1-254)");
  }
  room_params_ = p;
  self_ = self;
  state_ = RoomState::kInRoom;
  ++stats_.entries;
  next_heartbeat_ = now_ + config_.heartbeat_interval;
  if (has_passphrase()) {
    const bool deriving_this =
        derivation_.started() && derivation_.salt() == p.salt && derivation_.cost() == p.kdf;
    if ((!master_ || master_salt_ != p.salt || master_cost_ != p.kdf) && !deriving_this) {
      if (master_) {
        wipe(*master_);
        master_.reset();
      }
      derivation_.start(config_.passphrase, p.salt, p.kdf, config_.derive_on_this_thread);
    }
    key_timers();
  }
  for (const RoomMember& m : already_there) {
    add_member(m.id, m.announce, false);
  }
}

void RoomSession::on_member_joined(const RoomMember& member) {
  if (state_ == RoomState::kInRoom) {
    add_member(member.id, member.announce, true);
  }
}

void RoomSession::on_member_left(MemberId id) {
  ignored_[id] = false;
  if (Member* m = find(id)) {
    gone(*m, LeftBecause::kLeft);
    release(*m);
  }
}

void RoomSession::on_refused(RelayRefusal why) {
  if (is_final(why)) {
    forget_everyone(LeftBecause::kRelayLost);
    refuse(RoomRefusal::kRelay, "the relay refused: " + std::string(describe(why)));
    return;
  }
  if (state_ != RoomState::kRefused) {
    state_ = RoomState::kWaiting;
  }
}

void RoomSession::on_relay_lost() {
  forget_everyone(LeftBecause::kRelayLost);
  if (state_ != RoomState::kRefused) {
    state_ = RoomState::kWaiting;
  }
}

void RoomSession::refuse(RoomRefusal why, std::string text) {
  state_ = RoomState::kRefused;
  refusal_ = why;
  refusal_text_ = std::move(text);
  log().error("room: {}", refusal_text_);
}

// ---- members ----

void RoomSession::add_member(MemberId id, std::span<const std::uint8_t> announce, bool later) {
  if (id == kNoMember || id == kAllMembers || id == self_ || find(id) != nullptr) {
    drop(nullptr, id, Channel::kReliable, as_bytes(announce),
         wire_error(DropReason::kDuplicateId, "member.id"));
    return;
  }
  Member* slot = nullptr;
  for (std::size_t i = 0; i < config_.max_members && slot == nullptr; ++i) {
    slot = members_[i].stage == Stage::kFree ? &members_[i] : nullptr;
  }
  if (slot == nullptr) {
    ++stats_.over_capacity;
    ignored_[id] = true;
    if (warn_budget_.take(now_)) {
      log().warn("room: member {} ignored: {} members held already", id, config_.max_members);
    }
    return;
  }
  Member& m = *slot;
  m.id = id;
  m.stage = Stage::kAnnounced;
  m.later = later;
  m.sent_key = false;
  m.key_waiting = false;
  m.jitter = JitterBuffer(config_.jitter);
  m.stats = PersonStats{};
  m.last_heard = now_;
  m.budget_packets = config_.budget.packets_per_second * config_.budget.burst_seconds;
  m.budget_bytes = config_.budget.bytes_per_second * config_.budget.burst_seconds;
  m.budget_last = now_;
  std::snprintf(m.label.data(), m.label.size(), "member %u", static_cast<unsigned>(id));
  if (WireResult e = decode(as_bytes(announce), m.announce); !e.ok()) {
    drop(&m, id, Channel::kReliable, as_bytes(announce), e);
    return failed(m, "its announce does not decode");
  }
  if (m.announce.auth != room_params_.auth) {
    drop(&m, id, Channel::kReliable, as_bytes(announce),
         wire_error(DropReason::kUnauthenticated, "announce.auth"));
    return failed(m, room_params_.auth == AuthMode::kPassphrase
                         ? "it has no passphrase in a sealed room"
                         : "it has a passphrase in an open room");
  }
  if (!has_passphrase()) {
    return verified(m);  // an open room: nothing to prove
  }
  m.transcript = room_transcript(room_params_, self_, entry_.announce, id, m.announce);
  prepare(m);
}

void RoomSession::prepare(Member& m) {
  if (!master_ || m.prk || m.stage != Stage::kAnnounced) {
    return;
  }
  m.prk = room_pair_secret(*master_, m.transcript, self_, entry_.keys, m.id, m.announce.key);
  if (!m.prk) {
    return failed(m, "its exchange key is unusable");
  }
  if (!m.later) {
    send_key_message(m);  // it was there first: we prove first
    m.stage = Stage::kProved;
  }
  if (m.key_waiting) {
    m.key_waiting = false;
    on_key_message(m, m.key_message);
  }
}

void RoomSession::send_key_message(Member& m) {
  std::array<std::byte, kKeyMessageBytes> out{};
  if (seal_key_message(*m.prk, m.transcript, self_, m.id, config_.hello.site, sender_key_, out) ==
      0) {
    ++stats_.send_failures;
    return;
  }
  m.sent_key = true;
  ++stats_.key_messages_sent;
  transport_send(m.id, Channel::kReliable, out);
}

void RoomSession::on_key_message(Member& m, std::span<const std::byte> packet) {
  if (!has_passphrase() || m.stage == Stage::kVerified) {
    return drop(&m, m.id, Channel::kReliable, packet,
                wire_error(DropReason::kUnexpected, "key_message"));
  }
  if (!m.prk) {
    // Our master key is still being derived: keep the first one until it is there.
    if (m.key_waiting || packet.size() != kKeyMessageBytes) {
      return drop(&m, m.id, Channel::kReliable, packet,
                  wire_error(packet.size() != kKeyMessageBytes ? DropReason::kOutOfRange
                                                               : DropReason::kUnexpected,
                             "key_message"));
    }
    std::copy(packet.begin(), packet.end(), m.key_message.begin());
    m.key_waiting = true;
    return;
  }
  KeyGrant grant;
  if (WireResult e = open_key_message(*m.prk, m.transcript, m.id, self_, packet, grant); !e.ok()) {
    drop(&m, m.id, Channel::kReliable, packet, e);
    ++stats_.auth_failures;
    return failed(m,
                  "its key message does not open: another passphrase (or a relay that "
                  "changed what it said)");
  }
  m.site = grant.site;
  m.opener.emplace(grant.sender_key);
  if (!m.sent_key) {
    send_key_message(m);  // it proved first: only now does it get our key
  }
  verified(m);
}

void RoomSession::verified(Member& m) {
  m.stage = Stage::kVerified;
  m.last_heard = now_;
  ++stats_.verified;
  if (m.prk) {
    wipe(*m.prk);  // the pair's secret has done its work
    m.prk.reset();
  }
  log().info("room: {} verified{}{}", m.label.data(), m.site.empty() ? "" : " as ", m.site);
  send_to(m.id, Channel::kReliable, hello_bytes_);
  send_to(m.id, Channel::kReliable, map_bytes_);
}

void RoomSession::failed(Member& m, const char* why) {
  m.stage = Stage::kFailed;
  if (m.prk) {
    wipe(*m.prk);
    m.prk.reset();
  }
  if (warn_budget_.take(now_)) {
    log().warn("room: {} is shown to no one: {} ({} such lines held back)", m.label.data(), why,
               warn_budget_.held_back());
  }
}

void RoomSession::gone(Member& m, LeftBecause why) {
  if (m.stage == Stage::kVerified && m.hello) {
    ++stats_.people_left;
    push_event(RoomEventKind::kLeft, m.id, why);
    const auto end = std::remove(people_.begin(), people_.begin() + people_count_, m.id);
    people_count_ = static_cast<std::size_t>(end - people_.begin());
  }
  if (m.stage == Stage::kVerified) {
    m.stage = Stage::kGone;
  }
  m.opener.reset();
  m.jitter.reset();
  m.avatar_rx.reset();
  avatar_tx_.forget(m.id);
}

void RoomSession::release(Member& m) {
  m.stage = Stage::kFree;
  m.id = kNoMember;
  m.opener.reset();
  m.hello.reset();
  m.map.reset();
  m.site.clear();
  if (m.prk) {
    wipe(*m.prk);
    m.prk.reset();
  }
  m.key_waiting = false;
}

void RoomSession::forget_everyone(LeftBecause why) {
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    if (members_[i].stage != Stage::kFree) {
      gone(members_[i], why);
      release(members_[i]);
    }
  }
  self_ = kNoMember;
  ignored_.fill(false);
}

void RoomSession::leave(double now) {
  now_ = now;
  if (state_ == RoomState::kInRoom) {
    std::array<std::byte, kByeBytes> bye{};
    encode(Bye{ByeReason::kLeaving}, bye);
    send_to_verified(Channel::kReliable, bye);
  }
  forget_everyone(LeftBecause::kClosed);
  if (state_ != RoomState::kRefused) {
    state_ = RoomState::kWaiting;
  }
}

// ---- timers ----

void RoomSession::key_timers() {
  if (!derivation_.ready()) {
    return;
  }
  const Salt salt = derivation_.salt();
  const KdfCost cost = derivation_.cost();
  std::optional<Key> key = derivation_.take();
  if (!key) {
    return refuse(RoomRefusal::kKeyFailed,
                  "the passphrase key could not be derived (Argon2id ran out of memory)");
  }
  if (state_ != RoomState::kInRoom || salt != room_params_.salt || cost != room_params_.kdf) {
    wipe(*key);
    return;  // derived for an entry that is over
  }
  master_ = *key;
  wipe(*key);
  master_salt_ = salt;
  master_cost_ = cost;
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    if (members_[i].stage == Stage::kAnnounced) {
      prepare(members_[i]);
    }
  }
}

void RoomSession::poll(double now) {
  now_ = now;
  if (state_ != RoomState::kInRoom) {
    return;
  }
  key_timers();
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    Member& m = members_[i];
    if (m.stage == Stage::kVerified && now - m.last_heard > config_.heartbeat_timeout) {
      ++stats_.timeouts;
      if (warn_budget_.take(now)) {
        log().warn("room: {} ({}) timed out: nothing heard for {:.1f} s", m.label.data(),
                   m.hello ? std::string_view(m.hello->site) : std::string_view("no hello"),
                   now - m.last_heard);
      }
      gone(m, LeftBecause::kTimedOut);
    } else if (m.stage == Stage::kVerified) {
      send_avatar_chunks(m);
    }
  }
  if (now >= next_heartbeat_) {
    next_heartbeat_ = now + config_.heartbeat_interval;
    encode(Heartbeat{heartbeats_sent_++}, heartbeat_tx_);
    send_to_verified(Channel::kReliable, heartbeat_tx_);
  }
}

// ---- sending ----

bool RoomSession::everyone_verified() const {
  if (std::find(ignored_.begin(), ignored_.end(), true) != ignored_.end()) {
    return false;  // members we do not hold may be anyone
  }
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    const Stage s = members_[i].stage;
    if (s != Stage::kFree && s != Stage::kVerified) {
      return false;
    }
  }
  return true;
}

std::span<const std::byte> RoomSession::seal(Channel channel, std::span<const std::byte> inner) {
  if (!sealer_) {
    return inner;  // an open room
  }
  const std::size_t n = sealer_->seal(channel, inner, sealed_tx_);
  if (n == 0) {
    ++stats_.send_failures;
  }
  return std::span<const std::byte>(sealed_tx_).first(n);
}

bool RoomSession::transport_send(MemberId to, Channel channel, std::span<const std::byte> packet) {
  if (packet.empty()) {
    return false;
  }
  ++stats_.sends;
  if (!transport_.send(to, channel, as_u8(packet))) {
    ++stats_.send_failures;
    return false;
  }
  return true;
}

bool RoomSession::send_to(MemberId to, Channel channel, std::span<const std::byte> inner) {
  return transport_send(to, channel, seal(channel, inner));
}

bool RoomSession::send_to_verified(Channel channel, std::span<const std::byte> inner) {
  std::size_t verified = 0;
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    verified += members_[i].stage == Stage::kVerified ? 1 : 0;
  }
  if (verified == 0) {
    return false;
  }
  const std::span<const std::byte> packet = seal(channel, inner);  // once, for everyone
  if (everyone_verified()) {
    return transport_send(kAllMembers, channel, packet);
  }
  bool all = true;
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    if (members_[i].stage == Stage::kVerified) {
      all = transport_send(members_[i].id, channel, packet) && all;
    }
  }
  return all;
}

bool RoomSession::send_tracking(const TrackingFrame& frame, double sampled) {
  if (state_ != RoomState::kInRoom) {
    return false;
  }
  TrackingMessage message{tracking_sequence_, frame};
  message.frame.time = sampled;
  const TrackingEncoding encoded =
      encode_tracking(message, config_.hello.avatar.body.T_world_root.translation, tracking_tx_);
  if (encoded.bytes == 0) {
    ++stats_.send_failures;
    return false;
  }
  stats_.parts_not_sent += static_cast<std::uint64_t>(std::popcount(encoded.dropped_parts));
  if (!send_to_verified(Channel::kTracking, std::span(tracking_tx_).first(encoded.bytes))) {
    return false;
  }
  ++tracking_sequence_;
  ++stats_.tracking_sent;
  return true;
}

void RoomSession::set_hello(const Hello& hello) {
  Hello ours = hello;
  hello_bytes_ = encode_replacement_hello(config_.hello, ours, avatar_tx_.model(), "room");
  config_.hello = std::move(ours);
  if (state_ == RoomState::kInRoom) {
    send_to_verified(Channel::kReliable, hello_bytes_);
  }
}

void RoomSession::set_target_map(const TargetMap& map) {
  std::vector<std::byte> bytes;
  if (WireResult e = encode(map, bytes); !e.ok()) {
    throw Error(wire_message("room: target map", e));
  }
  config_.target_map = map;
  map_bytes_ = std::move(bytes);
  if (state_ == RoomState::kInRoom) {
    send_to_verified(Channel::kReliable, map_bytes_);
  }
}

// ---- receiving ----

void RoomSession::drop(Member* m, MemberId from, Channel channel, std::span<const std::byte> packet,
                       WireResult why) {
  if (m != nullptr) {
    ++m->stats.drops.by_reason[static_cast<std::size_t>(why.reason)];
    ++m->stats.drops.total;
  }
  std::array<char, 16> label{};
  std::snprintf(label.data(), label.size(), "member %u", static_cast<unsigned>(from));
  const int type = packet.empty() ? kNoType : std::to_integer<int>(packet[0]);
  drop_log_.drop(now_, label.data(), channel, type, why);
}

bool RoomSession::within_budget(Member& m, std::size_t bytes) {
  const PeerBudget& b = config_.budget;
  const double elapsed = std::max(0.0, now_ - m.budget_last);
  m.budget_last = std::max(m.budget_last, now_);
  m.budget_packets = std::min(b.packets_per_second * b.burst_seconds,
                              m.budget_packets + elapsed * b.packets_per_second) -
                     1.0;
  m.budget_bytes = std::min(b.bytes_per_second * b.burst_seconds,
                            m.budget_bytes + elapsed * b.bytes_per_second) -
                   static_cast<double>(bytes);
  return m.budget_packets >= 0.0 && m.budget_bytes >= 0.0;
}

void RoomSession::on_payload(MemberId from, Channel channel,
                             std::span<const std::uint8_t> payload) {
  const std::span<const std::byte> bytes = as_bytes(payload);
  Member* m = state_ == RoomState::kInRoom ? find(from) : nullptr;
  if (m == nullptr || m->stage == Stage::kGone) {
    return drop(m, from, channel, bytes, wire_error(DropReason::kUnknownPeer, "from"));
  }
  if (!within_budget(*m, bytes.size())) {
    ++stats_.floods;
    log().warn("room: {} sent more than {} packets or {} bytes a second: no longer listened to",
               m->label.data(), config_.budget.packets_per_second, config_.budget.bytes_per_second);
    gone(*m, LeftBecause::kFlooded);
    m->stage = Stage::kGone;
    return;
  }
  if (bytes.empty()) {
    return drop(m, from, channel, bytes, wire_error(DropReason::kEmpty, "payload"));
  }
  if (m->stage == Stage::kFailed) {
    return drop(m, from, channel, bytes, wire_error(DropReason::kUnauthenticated, "from"));
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  if (type == kKeyMessageType) {
    if (channel != Channel::kReliable) {
      return drop(m, from, channel, bytes, wire_error(DropReason::kWrongChannel, "key_message"));
    }
    return on_key_message(*m, bytes);
  }
  if (m->stage != Stage::kVerified) {
    return drop(m, from, channel, bytes, wire_error(DropReason::kUnauthenticated, "payload"));
  }
  if (!has_passphrase()) {
    if (is(type, MessageType::kSealed)) {
      return drop(m, from, channel, bytes, wire_error(DropReason::kUnexpected, "sealed"));
    }
    return dispatch(*m, channel, bytes);
  }
  if (!is(type, MessageType::kSealed)) {
    return drop(m, from, channel, bytes, wire_error(DropReason::kUnauthenticated, "payload"));
  }
  std::span<const std::byte> inner;
  if (WireResult e = m->opener->open(channel, bytes, plain_rx_, inner); !e.ok()) {
    return drop(m, from, channel, bytes, e);
  }
  dispatch(*m, channel, inner);
}

void RoomSession::dispatch(Member& m, Channel channel, std::span<const std::byte> inner) {
  const auto type = std::to_integer<std::uint8_t>(inner[0]);
  const bool on_tracking_channel = channel == Channel::kTracking;
  if (is(type, MessageType::kTracking) != on_tracking_channel) {
    return drop(
        &m, m.id, channel, inner,
        wire_error(is_known_type(type) ? DropReason::kWrongChannel : DropReason::kUnknownType,
                   "type"));
  }
  switch (static_cast<MessageType>(type)) {
    case MessageType::kTracking:
      return on_tracking(m, channel, inner);
    case MessageType::kHello:
      return on_hello(m, inner);
    case MessageType::kTargetMap:
      return on_target_map(m, inner);
    case MessageType::kHeartbeat: {
      Heartbeat h;
      if (WireResult e = decode(inner, h); !e.ok()) {
        return drop(&m, m.id, channel, inner, e);
      }
      ++m.stats.heartbeats;
      m.last_heard = now_;
      return;
    }
    case MessageType::kAvatarRequest:
      return on_avatar_request(m, inner);
    case MessageType::kAvatarData:
      return on_avatar_data(m, inner);
    case MessageType::kBye: {
      Bye b;
      if (WireResult e = decode(inner, b); !e.ok()) {
        return drop(&m, m.id, channel, inner, e);
      }
      log().info("room: {} said bye", m.label.data());
      return gone(m, LeftBecause::kBye);
    }
    default:
      return drop(
          &m, m.id, channel, inner,
          wire_error(is_known_type(type) ? DropReason::kUnexpected : DropReason::kUnknownType,
                     "type"));
  }
}

void RoomSession::on_hello(Member& m, std::span<const std::byte> inner) {
  Hello h;
  if (WireResult e = decode(inner, h); !e.ok()) {
    return drop(&m, m.id, Channel::kReliable, inner, e);
  }
  if (!m.site.empty() && h.site != m.site) {
    // The key message bound the member's site name: a hello under another one is a lie.
    drop(&m, m.id, Channel::kReliable, inner, wire_error(DropReason::kOutOfRange, "hello.site"));
    gone(m, LeftBecause::kBye);
    return failed(m, "its hello names another site than its key message");
  }
  m.last_heard = now_;
  ++m.stats.hellos;
  const bool first = !m.hello;
  m.hello = std::move(h);
  if (first) {
    m.jitter.reset();
    people_[people_count_++] = m.id;
    ++stats_.people_arrived;
    log().info("room: {} is {}{}", m.label.data(), m.hello->site, sealer_ ? " (sealed)" : "");
  }
  push_event(first ? RoomEventKind::kArrived : RoomEventKind::kHelloChanged, m.id);
}

void RoomSession::on_target_map(Member& m, std::span<const std::byte> inner) {
  TargetMap map;
  if (WireResult e = decode(inner, map); !e.ok()) {
    return drop(&m, m.id, Channel::kReliable, inner, e);
  }
  m.last_heard = now_;
  ++m.stats.target_maps;
  m.map = std::move(map);
  if (m.hello) {
    push_event(RoomEventKind::kTargetMapChanged, m.id);
  }
}

void RoomSession::on_tracking(Member& m, Channel channel, std::span<const std::byte> inner) {
  if (!m.hello) {
    return drop(&m, m.id, channel, inner, wire_error(DropReason::kNotStreaming, "hello"));
  }
  if (WireResult e =
          decode_tracking(inner, m.hello->avatar.body.T_world_root.translation, tracking_rx_);
      !e.ok()) {
    return drop(&m, m.id, channel, inner, e);
  }
  m.last_heard = now_;
  ++m.stats.tracking_received;
  ++stats_.tracking_received;
  m.jitter.push(tracking_rx_.sequence, tracking_rx_.frame, now_);
}

// ---- avatar files (net/avatar_transfer.h) ----

void RoomSession::on_avatar_request(Member& m, std::span<const std::byte> inner) {
  AvatarRequest request;
  if (WireResult e = decode(inner, request); !e.ok()) {
    return drop(&m, m.id, Channel::kReliable, inner, e);
  }
  m.last_heard = now_;
  if (!avatar_tx_.on_request(m.id, request.hash, now_)) {
    return drop(&m, m.id, Channel::kReliable, inner,
                wire_error(DropReason::kUnexpected, "avatar_request.hash"));
  }
  ++stats_.avatar_requests_received;
}

void RoomSession::on_avatar_data(Member& m, std::span<const std::byte> inner) {
  AvatarData chunk;
  if (WireResult e = decode(inner, chunk); !e.ok()) {
    return drop(&m, m.id, Channel::kReliable, inner, e);
  }
  m.last_heard = now_;
  const AvatarReceiveStatus before = m.avatar_rx.status();
  if (!m.avatar_rx.on_data(chunk)) {
    return drop(&m, m.id, Channel::kReliable, inner,
                wire_error(DropReason::kUnexpected, "avatar_data.hash"));
  }
  ++m.stats.avatar_chunks_received;
  const AvatarReceiveStatus after = m.avatar_rx.status();
  if (before == AvatarReceiveStatus::kReceiving && after != before) {
    if (after == AvatarReceiveStatus::kFailed) {
      log().warn("room: the avatar file from {} was abandoned: {}", m.label.data(),
                 m.avatar_rx.failure());
    }
    push_event(RoomEventKind::kAvatarFile, m.id);
  }
}

void RoomSession::send_avatar_chunks(Member& m) {
  if (!avatar_tx_.has_file()) {
    return;
  }
  // A few chunks at most per poll; the sender's pace decides when each is due. Each goes to the
  // member that asked only.
  for (int i = 0; i < 4; ++i) {
    const std::optional<AvatarData> chunk = avatar_tx_.next_chunk(m.id, now_);
    if (!chunk) {
      return;
    }
    const std::size_t n = encode(*chunk, avatar_chunk_tx_);
    if (n == 0 || !send_to(m.id, Channel::kReliable, std::span(avatar_chunk_tx_).first(n))) {
      avatar_tx_.forget(m.id);
      return;
    }
    ++stats_.avatar_chunks_sent;
  }
}

std::optional<AvatarHash> RoomSession::avatar_hash(MemberId person) const {
  const Hello* h = hello(person);
  return h ? parse_avatar_hash(h->avatar.model) : std::nullopt;
}

bool RoomSession::request_avatar(MemberId person) {
  const std::optional<AvatarHash> hash = avatar_hash(person);
  Member* m = find(person);
  if (!hash || m == nullptr) {
    return false;
  }
  std::array<std::byte, kAvatarRequestBytes> bytes{};
  encode(AvatarRequest{*hash}, bytes);
  m->avatar_rx.expect(*hash);
  log().info("room: asking {} for their avatar file {}", m->label.data(),
             to_hex(*hash).substr(0, 12));
  return send_to(person, Channel::kReliable, bytes);
}

const AvatarReceiver* RoomSession::avatar_download(MemberId person) const {
  const Member* m = find_person(person);
  return m ? &m->avatar_rx : nullptr;
}

// ---- the site's side ----

void RoomSession::push_event(RoomEventKind kind, MemberId person, LeftBecause why) {
  for (std::size_t i = events_read_; i < events_.size(); ++i) {
    if (events_[i].kind == kind && events_[i].person == person && kind != RoomEventKind::kLeft) {
      ++stats_.events_coalesced;
      return;
    }
  }
  if (events_.size() == events_.capacity()) {
    if (events_read_ == 0) {
      ++stats_.events_coalesced;  // nobody takes them: the site runtime is not reading
      return;
    }
    events_.erase(events_.begin(), events_.begin() + static_cast<std::ptrdiff_t>(events_read_));
    events_read_ = 0;
  }
  events_.push_back({kind, person, why});
}

bool RoomSession::next_event(RoomEvent& out) {
  if (events_read_ >= events_.size()) {
    events_.clear();
    events_read_ = 0;
    return false;
  }
  out = events_[events_read_++];
  return true;
}

const Hello* RoomSession::hello(MemberId person) const {
  const Member* m = find_person(person);
  return m ? &*m->hello : nullptr;
}

const TargetMap* RoomSession::target_map(MemberId person) const {
  const Member* m = find_person(person);
  return m && m->map ? &*m->map : nullptr;
}

Playout RoomSession::next_playout(MemberId person, double now) {
  for (std::size_t i = 0; i < config_.max_members; ++i) {
    Member& m = members_[i];
    if (m.stage == Stage::kVerified && m.id == person && m.hello) {
      return m.jitter.pop(now);
    }
  }
  return {};
}

const JitterStats* RoomSession::jitter(MemberId person) const {
  const Member* m = find_person(person);
  return m ? &m->jitter.stats() : nullptr;
}

const PersonStats* RoomSession::person_stats(MemberId person) const {
  const Member* m = find_person(person);
  return m ? &m->stats : nullptr;
}

}  // namespace deixis::net
