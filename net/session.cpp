#include "net/session.h"

#include <sodium.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/error.h"
#include "net/passphrase.h"

namespace deixis::net {

std::string_view state_name(SessionState state) {
  switch (state) {
    case SessionState::kIdle:
      return "idle";
    case SessionState::kWaiting:
      return "waiting";
    case SessionState::kConnecting:
      return "connecting";
    case SessionState::kHandshake:
      return "handshake";
    case SessionState::kHello:
      return "hello";
    case SessionState::kStreaming:
      return "streaming";
    case SessionState::kRefused:
      return "refused";
  }
  return "?";
}

std::string_view end_cause_name(EndCause cause) {
  switch (cause) {
    case EndCause::kNone:
      return "none";
    case EndCause::kConnectFailed:
      return "connection attempt failed";
    case EndCause::kHandshakeTimedOut:
      return "handshake timed out";
    case EndCause::kTimedOut:
      return "timed out";
    case EndCause::kByeFromPeer:
      return "the peer said bye";
    case EndCause::kRefusedPeer:
      return "we refused the peer";
    case EndCause::kTransportLost:
      return "connection lost";
    case EndCause::kClosed:
      return "closed";
    case EndCause::kFlooded:
      return "cut off for flooding";
  }
  return "?";
}

namespace {

// A sealed packet needs room for the padded inner packet and the overhead.
constexpr std::size_t kSealedBufferBytes = kMaxPacketBytes + kSealOverheadBytes;
// A stranger's handshake takes a join and perhaps a bye: anything more is not a handshake.
constexpr int kMaxStrangerPackets = 4;
// Failed proofs from an address are forgotten after this long without one (s).
constexpr double kForgetFailuresAfter = 600.0;

// A packet's expected channel.
Channel channel_of(std::uint8_t type) {
  return type == static_cast<std::uint8_t>(MessageType::kTracking) ? Channel::kTracking
                                                                   : Channel::kReliable;
}

bool is_type(std::uint8_t type, MessageType t) {
  return type == static_cast<std::uint8_t>(t);
}

std::string cost_text(const KdfCost& c) {
  return std::to_string(c.opslimit) + " passes, " + std::to_string(c.memlimit_kib / 1024) + " MiB";
}

}  // namespace

Session::Session(Link& link, SessionConfig config)
    : link_(link),
      config_(std::move(config)),
      drop_log_(config_.logger),
      jitter_(config_.jitter),
      padded_tx_(kMaxPacketBytes),
      sealed_tx_(kSealedBufferBytes),
      plain_rx_(kMaxPacketBytes) {
  if (config_.avatar_file) {
    // Our hello names the file by its hash: a peer that has it cached never asks for it.
    avatar_tx_ = AvatarSender(*config_.avatar_file, "session: our avatar file");
    config_.hello.avatar.model = avatar_tx_.model();
    avatar_chunk_tx_.resize(kAvatarDataHeaderBytes + kAvatarChunkMaxBytes);
  }
  if (WireResult e = encode(config_.hello, hello_bytes_); !e.ok()) {
    throw Error(wire_message("session: our hello", e));
  }
  if (WireResult e = encode(config_.target_map, map_bytes_); !e.ok()) {
    throw Error(wire_message("session: our target map", e));
  }
  if (!sodium_ready()) {
    throw Error("session: libsodium failed to initialise");
  }
  if (config_.max_pending == 0 || config_.max_pending_per_address == 0 ||
      config_.max_events_per_service == 0) {
    throw Error(
        "session: max_pending, max_pending_per_address and max_events_per_service must "
        "be at least 1");
  }
  pending_.reserve(config_.max_pending);
  reconnect_delay_ = config_.reconnect_min;
  if (is_host() && has_passphrase()) {
    const KdfCost& c = config_.kdf;
    if (c.opslimit < kMinKdfOps || c.opslimit > kMaxKdfOps || c.memlimit_kib < kMinKdfMemKib ||
        c.memlimit_kib > kMaxKdfMemKib) {
      throw Error("session: the passphrase key cost (" + cost_text(c) +
                  ") is outside what joiners accept");
    }
    // One salt per hosting session until failed proofs pile up (host_key_timers); the key is
    // derived off this thread, and joins that arrive meanwhile wait for it.
    random_bytes(key_.salt);
    key_.cost = c;
    derivation_.start(config_.passphrase, key_.salt, key_.cost, config_.derive_on_this_thread);
  }
}

Session::~Session() {
  for (HostKey* k : {&key_, &previous_key_}) {
    if (k->master) {
      wipe(*k->master);
    }
  }
}

spdlog::logger& Session::log() const {
  return config_.logger ? *config_.logger : *spdlog::default_logger_raw();
}

bool Session::connected() const {
  return status_.state == SessionState::kHandshake || status_.state == SessionState::kHello ||
         status_.state == SessionState::kStreaming;
}

bool Session::serving() const {
  return status_.state == SessionState::kHello || status_.state == SessionState::kStreaming;
}

void Session::warn_limited(double now, std::string_view what) {
  if (warn_budget_.take(now)) {
    log().warn("net: {} ({} similar lines held back)", what, warn_budget_.held_back());
  }
}

// ---------------------------------------------------------------- driving

void Session::start(double now) {
  status_.last_heard = now;
  if (is_host()) {
    status_.state = SessionState::kWaiting;
    log().info("net: {} listening", config_.hello.site);
    return;
  }
  attempt(now);
}

void Session::service(double now, std::uint32_t wait_ms) {
  // Bounded: a flood leaves its excess for the next call instead of starving the caller's loop.
  std::size_t handled = 0;
  for (LinkEvent e = link_.next_event(wait_ms); e.kind != LinkEvent::Kind::kNone;
       e = link_.next_event(0)) {
    on_event(e, now);
    if (++handled == config_.max_events_per_service) {
      ++stats_.service_bounded;
      break;
    }
  }
  timers(now);
  status_.round_trip_ms = link_.round_trip_ms(peer_);
}

void Session::on_event(const LinkEvent& e, double now) {
  if (e.kind == LinkEvent::Kind::kConnected) {
    return on_connected(e.peer, now);
  }
  if (e.peer != peer_ || peer_ == kNoPeer) {
    if (Pending* p = is_host() ? find_pending(e.peer) : nullptr) {
      if (e.kind == LinkEvent::Kind::kDisconnected) {
        remove_pending(e.peer);
      } else if (e.kind == LinkEvent::Kind::kReceived) {
        on_stranger_packet(*p, e.channel, e.bytes, now);
      }
    }
    return;  // a connection we let go: whatever it says is late
  }
  if (e.kind == LinkEvent::Kind::kDisconnected) {
    on_disconnected(e.data, now);
  } else if (e.kind == LinkEvent::Kind::kReceived) {
    on_packet(e.channel, e.bytes, now);
  }
}

void Session::timers(double now) {
  if (is_host()) {
    host_key_timers();
    pending_timers(now);
  }
  switch (status_.state) {
    case SessionState::kWaiting:
      if (!is_host() && now >= status_.next_attempt) {
        attempt(now);
      }
      break;
    case SessionState::kConnecting:
      if (now >= deadline_) {
        link_.disconnect(peer_, 0);
        end_connection(EndCause::kConnectFailed, now);
      }
      break;
    case SessionState::kHandshake:
      if (!is_host() && welcome_seen_ && !join_sent_ && derivation_.ready()) {
        send_join(now);
      } else if (now >= deadline_) {
        log().warn("net: handshake with {} did not finish in {:.1f} s", peer_name(),
                   config_.handshake_timeout);
        send_bye(ByeReason::kProtocolError);
        link_.disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kProtocolError));
        end_connection(EndCause::kHandshakeTimedOut, now);
      }
      break;
    case SessionState::kHello:
    case SessionState::kStreaming:
      if (now - status_.last_heard > config_.heartbeat_timeout) {
        ++status_.timeouts;
        log().warn("net: {} timed out: nothing heard for {:.1f} s", peer_name(),
                   now - status_.last_heard);
        link_.disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kLeaving));
        end_connection(EndCause::kTimedOut, now);
      } else if (now >= next_heartbeat_) {
        std::array<std::byte, kHeartbeatBytes> bytes{};
        encode(Heartbeat{heartbeats_sent_++}, bytes);
        send_reliable(bytes);
        next_heartbeat_ = now + config_.heartbeat_interval;
      }
      send_avatar_chunks(now);
      break;
    case SessionState::kIdle:
    case SessionState::kRefused:
      break;
  }
}

void Session::attempt(double now) {
  ++status_.attempts;
  peer_ = link_.connect();
  label_peer(peer_);
  if (peer_ == kNoPeer) {
    end_connection(EndCause::kConnectFailed, now);
    return;
  }
  status_.state = SessionState::kConnecting;
  deadline_ = now + config_.connect_timeout;
}

void Session::schedule_attempt(double now) {
  status_.state = SessionState::kWaiting;
  status_.next_attempt = now + reconnect_delay_;
  reconnect_delay_ = std::min(config_.reconnect_max, reconnect_delay_ * 2.0);
}

bool Session::send_tracking(const TrackingFrame& frame) {
  if (status_.state != SessionState::kStreaming) {
    return false;
  }
  const TrackingEncoding encoded =
      encode_tracking({tracking_sequence_, frame},
                      config_.hello.avatar.body.T_world_root.translation, tracking_tx_);
  if (encoded.bytes == 0) {
    return false;
  }
  ++tracking_sequence_;
  stats_.parts_not_sent += static_cast<std::uint64_t>(std::popcount(encoded.dropped_parts));
  std::span<const std::byte> packet = std::span(tracking_tx_).first(encoded.bytes);
  if (sealer_) {
    const std::size_t size = sealer_->seal(Channel::kTracking, packet, sealed_tx_);
    if (size == 0) {
      ++stats_.send_failures;
      return false;
    }
    packet = std::span(sealed_tx_).first(size);
  }
  if (!link_.send(peer_, Channel::kTracking, packet)) {
    ++stats_.send_failures;
    return false;
  }
  ++stats_.packets_sent;
  stats_.bytes_sent += packet.size();
  ++stats_.tracking_sent;
  return true;
}

Playout Session::next_frame(double now) {
  return jitter_.pop(now);
}

void Session::set_hello(const Hello& hello) {
  Hello ours = hello;
  hello_bytes_ = encode_replacement_hello(config_.hello, ours, avatar_tx_.model(), "session");
  config_.hello = std::move(ours);
  if (serving()) {
    send_reliable(hello_bytes_);
  }
}

void Session::set_target_map(const TargetMap& map) {
  std::vector<std::byte> bytes;
  if (WireResult e = encode(map, bytes); !e.ok()) {
    throw Error(wire_message("session: target map", e));
  }
  config_.target_map = map;
  map_bytes_ = std::move(bytes);
  if (serving()) {
    send_reliable(map_bytes_);
  }
}

void Session::close(double now) {
  if (connected()) {
    send_bye(ByeReason::kLeaving);
    link_.disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kLeaving));
  } else if (status_.state == SessionState::kConnecting) {
    link_.disconnect(peer_, 0);
  }
  while (!pending_.empty()) {
    let_go(pending_.back().peer, ByeReason::kLeaving);
  }
  end_connection(EndCause::kClosed, now);
  status_.state = SessionState::kIdle;
}

// ---------------------------------------------------------------- sending

bool Session::send_to(PeerId peer, std::span<const std::byte> packet) {
  if (!link_.send(peer, Channel::kReliable, packet)) {
    ++stats_.send_failures;
    return false;
  }
  ++stats_.packets_sent;
  stats_.bytes_sent += packet.size();
  return true;
}

bool Session::send_reliable(std::span<const std::byte> packet) {
  std::span<const std::byte> out = packet;
  if (sealer_) {
    // Padded to a size bucket first, so that sizes do not tell name lengths.
    const std::size_t padded = pad(packet, padded_tx_);
    const std::size_t size =
        padded == 0
            ? 0
            : sealer_->seal(Channel::kReliable, std::span(padded_tx_).first(padded), sealed_tx_);
    if (size == 0) {
      ++stats_.send_failures;
      return false;
    }
    out = std::span(sealed_tx_).first(size);
  }
  return send_to(peer_, out);
}

bool Session::send_bye(ByeReason reason) {
  std::array<std::byte, kByeBytes> bytes{};
  encode(Bye{reason}, bytes);
  return send_reliable(bytes);
}

void Session::send_hello_and_map() {
  send_reliable(hello_bytes_);
  send_reliable(map_bytes_);
}

// ---------------------------------------------------------------- transitions

void Session::label_peer(PeerId peer) {
  const std::string_view name = link_.peer_name(peer);
  const std::size_t n = std::min(name.size(), peer_label_.size() - 1);
  std::copy_n(name.begin(), n, peer_label_.begin());
  peer_label_[n] = '\0';
}

void Session::begin_connection(PeerId peer, double now) {
  peer_ = peer;
  label_peer(peer);
  status_.state = SessionState::kHandshake;
  status_.last_heard = now;
  deadline_ = now + config_.handshake_timeout;
  welcome_seen_ = false;
  join_sent_ = false;
  exchange_keys_.reset();
  peer_site_.clear();
  sealer_.reset();
  opener_.reset();
  budget_ = Bucket{config_.budget.packets_per_second * config_.budget.burst_seconds,
                   config_.budget.bytes_per_second * config_.budget.burst_seconds, now};
  heartbeats_sent_ = 0;
  tracking_sequence_ = 0;
  remote_hello_.reset();
  remote_map_.reset();
  jitter_.reset();
}

void Session::on_connected(PeerId peer, double now) {
  if (is_host()) {
    return on_stranger(peer, now);
  }
  if (status_.state != SessionState::kConnecting || peer != peer_) {
    link_.disconnect(peer, 0);  // a connection we no longer wanted (closed or refused meanwhile)
    return;
  }
  begin_connection(peer, now);
  log().info("net: {} connected to {}", config_.hello.site, peer_name());
}

void Session::on_disconnected(std::uint32_t code, double now) {
  const bool was_connecting = status_.state == SessionState::kConnecting;
  // Disconnect data is not authenticated: it can end a connection (anyone on the path can do
  // that), but it can only refuse us for good while the handshake is still under way. After it,
  // it means "transport lost", and the joiner reconnects.
  const bool authenticated_phase = serving();
  if (code != 0 && code <= kMaxByeReason && !authenticated_phase) {
    const auto reason = static_cast<ByeReason>(code);
    status_.last_bye = reason;
    if (!is_host() && is_refusal(reason)) {
      log().warn("net: {} refused us: {}", peer_name(), bye_reason_name(reason));
      end_connection(EndCause::kByeFromPeer, now);
      status_.state = SessionState::kRefused;
      return;
    }
  }
  if (!was_connecting) {
    log().info("net: {} disconnected", peer_name());
  }
  end_connection(was_connecting ? EndCause::kConnectFailed : EndCause::kTransportLost, now);
}

void Session::authenticated(const Key& prk, std::string_view joiner_site,
                            std::string_view host_site) {
  const SessionKeys keys = derive_session_keys(prk, joiner_site, host_site, is_host());
  sealer_.emplace(keys.send);
  opener_.emplace(keys.receive);
}

void Session::enter_hello(double now) {
  status_.state = SessionState::kHello;
  status_.last_heard = now;
  next_heartbeat_ = now + config_.heartbeat_interval;
  send_hello_and_map();
}

void Session::refuse(ByeReason reason, double now) {
  warn_limited(
      now, "refusing " + std::string(peer_name()) + ": " + std::string(bye_reason_name(reason)));
  send_bye(reason);
  link_.disconnect(peer_, static_cast<std::uint32_t>(reason));
  status_.last_bye = reason;
  if (reason == ByeReason::kAuthenticationFailed) {
    ++status_.auth_failures;
  }
  end_connection(EndCause::kRefusedPeer, now);
  // A joiner cannot fix a refusal by retrying; a host listens for the next peer.
  if (!is_host() && is_refusal(reason)) {
    status_.state = SessionState::kRefused;
  }
}

void Session::cut_off(double now) {
  ++stats_.floods_cut;
  log().warn("net: cutting off {}: more than {:.0f} packets or {:.0f} bytes a second", peer_name(),
             config_.budget.packets_per_second, config_.budget.bytes_per_second);
  send_bye(ByeReason::kFlooding);
  link_.disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kFlooding));
  status_.last_bye = ByeReason::kFlooding;
  end_connection(EndCause::kFlooded, now);
}

void Session::end_connection(EndCause cause, double now) {
  status_.last_end = cause;
  peer_ = kNoPeer;
  sealer_.reset();
  opener_.reset();
  exchange_keys_.reset();
  jitter_.reset();
  avatar_tx_.forget(0);
  avatar_rx_.reset();
  if (is_host()) {
    status_.state = SessionState::kWaiting;
  } else {
    schedule_attempt(now);
  }
}

// ---------------------------------------------------------------- host: strangers

Session::Pending* Session::find_pending(PeerId peer) {
  const auto it = std::find_if(pending_.begin(), pending_.end(),
                               [peer](const Pending& p) { return p.peer == peer; });
  return it == pending_.end() ? nullptr : &*it;
}

std::size_t Session::pending_from(std::uint32_t address) const {
  return static_cast<std::size_t>(
      std::count_if(pending_.begin(), pending_.end(),
                    [address](const Pending& p) { return p.address == address; }));
}

void Session::remove_pending(PeerId peer) {
  const auto it = std::find_if(pending_.begin(), pending_.end(),
                               [peer](const Pending& p) { return p.peer == peer; });
  if (it != pending_.end()) {
    pending_.erase(it);
  }
}

// A stranger has no keys yet: its bye goes plain, on the reliable channel.
void Session::send_plain_bye(PeerId peer, ByeReason reason) {
  std::array<std::byte, kByeBytes> bye{};
  encode(Bye{reason}, bye);
  send_to(peer, bye);
}

void Session::let_go(PeerId peer, ByeReason reason) {
  link_.disconnect(peer, static_cast<std::uint32_t>(reason));
  remove_pending(peer);
}

// Makes room for one: the oldest stranger of the address that holds the most.
void Session::evict_one(double now) {
  const Pending* victim = nullptr;
  std::size_t most = 0;
  for (const Pending& p : pending_) {
    const std::size_t n = pending_from(p.address);
    if (victim == nullptr || n > most || (n == most && p.since < victim->since)) {
      victim = &p;
      most = n;
    }
  }
  if (victim != nullptr) {
    ++strangers_.evicted;
    warn_limited(
        now, "handshake table full: letting go of " + std::string(link_.peer_name(victim->peer)));
    let_go(victim->peer, ByeReason::kTryLater);
  }
}

void Session::on_stranger(PeerId peer, double now) {
  ++status_.attempts;
  if (status_.state == SessionState::kIdle || status_.state == SessionState::kRefused) {
    link_.disconnect(peer, static_cast<std::uint32_t>(ByeReason::kLeaving));
    return;
  }
  // An open session may say busy at once (it has nothing to hide); one with a passphrase says so
  // only to a peer that proved it.
  if (!has_passphrase() && serving()) {
    ++strangers_.busy;
    link_.disconnect(peer, static_cast<std::uint32_t>(ByeReason::kBusy));
    return;
  }
  const std::uint32_t address = link_.peer_address(peer);
  if (held_back(address, now)) {
    // An address backing off after failed proofs costs us no welcome (and no key pair).
    ++strangers_.held_back;
    link_.disconnect(peer, static_cast<std::uint32_t>(ByeReason::kTryLater));
    return;
  }
  if (pending_from(address) >= config_.max_pending_per_address) {
    ++strangers_.over_budget;
    warn_limited(now, "turning away " + std::string(link_.peer_name(peer)) +
                          ": too many handshakes from its address");
    link_.disconnect(peer, static_cast<std::uint32_t>(ByeReason::kTryLater));
    return;
  }
  if (pending_.size() >= config_.max_pending) {
    evict_one(now);
  }
  ++strangers_.connected;
  Pending& p = pending_.emplace_back();
  p.peer = peer;
  p.address = address;
  p.since = now;
  p.deadline = now + config_.pending_timeout;
  random_bytes(p.welcome.host_challenge);
  if (has_passphrase()) {
    p.welcome.auth = AuthMode::kPassphrase;
    p.welcome.salt = key_.salt;
    p.welcome.kdf = key_.cost;
    p.keys = make_exchange_keys();
    p.welcome.host_key = p.keys.public_key;
  }
  encode(p.welcome, scratch_);
  send_to(peer, scratch_);
}

void Session::on_stranger_packet(Pending& p, Channel channel, std::span<const std::byte> bytes,
                                 double now) {
  ++stats_.packets_received;
  stats_.bytes_received += bytes.size();
  if (++p.packets > kMaxStrangerPackets) {
    ++strangers_.chatty;
    warn_limited(now, "letting go of " + std::string(link_.peer_name(p.peer)) +
                          ": more packets than a handshake needs");
    return let_go(p.peer, ByeReason::kProtocolError);
  }
  const std::uint8_t type = bytes.empty() ? 0 : std::to_integer<std::uint8_t>(bytes[0]);
  if (is_type(type, MessageType::kBye) && channel == Channel::kReliable) {
    return let_go(p.peer, ByeReason::kLeaving);
  }
  if (!is_type(type, MessageType::kJoin) || channel != Channel::kReliable || p.join) {
    drop_log_.drop(
        now, link_.peer_name(p.peer), channel, bytes.empty() ? kNoType : type,
        wire_error(has_passphrase() ? DropReason::kUnauthenticated : DropReason::kUnexpected,
                   "handshake"));
    return;
  }
  Join join;
  if (WireResult e = decode(bytes, join); !e.ok()) {
    drop_log_.drop(now, link_.peer_name(p.peer), channel, type, e);
    if (e.reason == DropReason::kWrongVersion) {
      send_plain_bye(p.peer, ByeReason::kVersionMismatch);
      let_go(p.peer, ByeReason::kVersionMismatch);
    }
    return;
  }
  p.join = join;
  verify_join(p, now);
}

bool Session::held_back(std::uint32_t address, double now) const {
  for (const AddressRecord& r : addresses_) {
    if (r.failures > 0 && r.address == address) {
      return now < r.blocked_until;
    }
  }
  return false;
}

Session::AddressRecord& Session::record_of(std::uint32_t address, double now) {
  AddressRecord* oldest = &addresses_[0];
  for (AddressRecord& r : addresses_) {
    if (r.failures > 0 && r.address == address) {
      if (now - r.last_failure > kForgetFailuresAfter) {
        r = AddressRecord{address, 0, -1e300, 0.0};
      }
      return r;
    }
    if (r.last_failure < oldest->last_failure) {
      oldest = &r;
    }
  }
  *oldest = AddressRecord{address, 0, -1e300, 0.0};
  return *oldest;
}

void Session::failed_proof(std::uint32_t address, double now) {
  ++status_.auth_failures;
  AddressRecord& r = record_of(address, now);
  ++r.failures;
  r.last_failure = now;
  if (r.failures > config_.free_failures) {
    const double wait = std::min(config_.max_backoff,
                                 std::ldexp(1.0, static_cast<int>(std::min<std::size_t>(
                                                     r.failures - config_.free_failures - 1, 16))));
    r.blocked_until = now + wait;
  }
  // Guesses cost a fresh Argon2id per salt: draw a new one now and then, so that nothing an
  // attacker computed for the old salt stays useful.
  if (++failures_since_rotation_ >= config_.rotate_salt_after && !derivation_.started()) {
    failures_since_rotation_ = 0;
    Salt salt{};
    random_bytes(salt);
    derivation_.start(config_.passphrase, salt, key_.cost, config_.derive_on_this_thread);
  }
}

void Session::host_key_timers() {
  if (!derivation_.ready()) {
    return;
  }
  const Salt salt = derivation_.salt();
  std::optional<Key> master = derivation_.take();
  if (!master) {
    log().error("net: cannot derive the passphrase key ({}): Argon2id ran out of memory?",
                cost_text(key_.cost));
    return;
  }
  if (key_.master) {  // a rotation: strangers welcomed with the old salt keep it
    previous_key_ = key_;
    ++strangers_.salts_rotated;
  }
  key_.salt = salt;
  key_.master = master;
  wipe(*master);
  // Joins that waited for the key are verified by pending_timers(), which runs right after.
}

const Session::HostKey* Session::host_key_for(const Salt& salt) const {
  for (const HostKey* k : {&key_, &previous_key_}) {
    if (k->master && k->salt == salt) {
      return k;
    }
  }
  return nullptr;
}

void Session::pending_timers(double now) {
  for (std::size_t i = 0; i < pending_.size();) {
    Pending& p = pending_[i];
    if (now >= p.deadline) {
      ++strangers_.timed_out;
      let_go(p.peer, ByeReason::kProtocolError);
      continue;
    }
    if (p.join && host_key_for(p.welcome.salt) != nullptr) {
      const PeerId id = p.peer;
      verify_join(p, now);
      if (i < pending_.size() && pending_[i].peer == id) {
        ++i;
      }
      continue;
    }
    ++i;
  }
}

void Session::verify_join(Pending& p, double now) {
  const Join& join = *p.join;
  const PeerId peer = p.peer;
  if (join.auth != p.welcome.auth) {
    const ByeReason reason =
        has_passphrase() ? ByeReason::kPassphraseRequired : ByeReason::kPassphraseUnexpected;
    send_plain_bye(peer, reason);
    warn_limited(now, "refusing " + std::string(link_.peer_name(peer)) + ": " +
                          std::string(bye_reason_name(reason)));
    return let_go(peer, reason);
  }
  if (!has_passphrase()) {
    return serve(p, std::nullopt, "", now);
  }
  const HostKey* key = host_key_for(p.welcome.salt);
  if (key == nullptr) {
    return;  // the key is still being derived: pending_timers() comes back to it
  }
  AddressRecord& record = record_of(p.address, now);
  if (now < record.blocked_until) {
    ++strangers_.held_back;
    send_plain_bye(peer, ByeReason::kTryLater);
    warn_limited(now, "holding back " + std::string(link_.peer_name(peer)) + " for " +
                          std::to_string(static_cast<int>(record.blocked_until - now + 0.5)) +
                          " s after failed proofs from its address");
    return let_go(peer, ByeReason::kTryLater);
  }
  const Key transcript = transcript_of(p.welcome, join);
  std::optional<Key> prk =
      handshake_secret(*key->master, transcript, p.keys, join.joiner_key, true);
  std::optional<std::string> site;
  if (prk) {
    site = open_join_proof(*prk, transcript, join.proof);
  }
  if (!site) {
    failed_proof(p.address, now);
    send_plain_bye(peer, ByeReason::kAuthenticationFailed);
    warn_limited(now, "refusing " + std::string(link_.peer_name(peer)) + ": " +
                          std::string(bye_reason_name(ByeReason::kAuthenticationFailed)));
    if (prk) {
      wipe(*prk);
    }
    return let_go(peer, ByeReason::kAuthenticationFailed);
  }
  serve(p, prk, *site, now);
  wipe(*prk);
}

// The stranger completed its handshake: it is served, unless another peer already is.
void Session::serve(Pending& p, const std::optional<Key>& prk, const std::string& joiner_site,
                    double now) {
  const PeerId peer = p.peer;
  if (serving()) {
    ++strangers_.busy;
    send_plain_bye(peer, ByeReason::kBusy);
    return let_go(peer, ByeReason::kBusy);
  }
  Accept accept;
  const Key transcript = transcript_of(p.welcome, *p.join);
  if (prk) {
    accept.proof = seal_accept_proof(*prk, transcript, joiner_site, config_.hello.site);
  }
  remove_pending(peer);  // `p` is gone from here on
  begin_connection(peer, now);
  peer_site_ = joiner_site;
  encode(accept, scratch_);
  send_to(peer, scratch_);  // plain: the joiner needs it to check us and derive the keys
  if (prk) {
    authenticated(*prk, joiner_site, config_.hello.site);
  }
  log().info("net: {} connected to {}", config_.hello.site, peer_name());
  enter_hello(now);
}

// ---------------------------------------------------------------- receiving

void Session::drop(Channel channel, std::span<const std::byte> packet, WireResult why, double now) {
  const int type = packet.empty() ? kNoType : std::to_integer<int>(packet[0]);
  drop_log_.drop(now, peer_name(), channel, type, why);
}

bool Session::within_budget(std::size_t bytes, double now) {
  const PeerBudget& b = config_.budget;
  const double elapsed = std::max(0.0, now - budget_.last);
  budget_.last = std::max(budget_.last, now);
  budget_.packets = std::min(b.packets_per_second * b.burst_seconds,
                             budget_.packets + elapsed * b.packets_per_second) -
                    1.0;
  budget_.bytes =
      std::min(b.bytes_per_second * b.burst_seconds, budget_.bytes + elapsed * b.bytes_per_second) -
      static_cast<double>(bytes);
  return budget_.packets >= 0.0 && budget_.bytes >= 0.0;
}

void Session::on_packet(Channel channel, std::span<const std::byte> bytes, double now) {
  ++stats_.packets_received;
  stats_.bytes_received += bytes.size();
  if (!within_budget(bytes.size(), now)) {
    return cut_off(now);
  }
  if (bytes.empty()) {
    drop(channel, bytes, wire_error(DropReason::kEmpty, "packet"), now);
    return;
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  const bool is_sealed = is_type(type, MessageType::kSealed);
  if (opener_) {
    // A passphrase session after the handshake: only sealed packets, from the peer's key.
    if (!is_sealed) {
      drop(channel, bytes, wire_error(DropReason::kUnauthenticated, "packet"), now);
      return;
    }
    std::span<const std::byte> inner;
    if (WireResult e = opener_->open(channel, bytes, plain_rx_, inner); !e.ok()) {
      drop(channel, bytes, e, now);
      return;
    }
    if (channel == Channel::kReliable) {
      inner = unpad(inner);
      if (inner.empty()) {
        drop(channel, bytes, wire_error(DropReason::kOutOfRange, "sealed.padding"), now);
        return;
      }
    }
    if (inner.empty() || is_type(std::to_integer<std::uint8_t>(inner[0]), MessageType::kSealed)) {
      drop(channel, inner, wire_error(DropReason::kUnexpected, "sealed.inner"), now);
      return;
    }
    dispatch(channel, inner, now);
    return;
  }
  if (is_sealed) {
    drop(channel, bytes,
         wire_error(has_passphrase() ? DropReason::kUnauthenticated : DropReason::kUnexpected,
                    "sealed"),
         now);
    return;
  }
  // Before the handshake has finished, a passphrase session takes handshake messages only.
  const bool handshake_message =
      is_type(type, MessageType::kWelcome) || is_type(type, MessageType::kJoin) ||
      is_type(type, MessageType::kAccept) || is_type(type, MessageType::kBye);
  if (has_passphrase() && is_known_type(type) && !handshake_message) {
    drop(channel, bytes, wire_error(DropReason::kUnauthenticated, "packet"), now);
    return;
  }
  dispatch(channel, bytes, now);
}

template <class Message, class Handle>
void Session::accept(Channel channel, std::span<const std::byte> packet, bool allowed, double now,
                     Handle&& handle) {
  if (!allowed) {
    drop(channel, packet, wire_error(DropReason::kUnexpected, "state"), now);
    return;
  }
  Message m;
  if (const WireResult result = decode(packet, m); !result.ok()) {
    drop(channel, packet, result, now);
    // A peer speaking another protocol version gets told so, rather than waiting out a time-out.
    if (result.reason == DropReason::kWrongVersion && status_.state == SessionState::kHandshake) {
      refuse(ByeReason::kVersionMismatch, now);
    }
    return;
  }
  handle(std::move(m));
}

void Session::dispatch(Channel channel, std::span<const std::byte> packet, double now) {
  const auto type = std::to_integer<std::uint8_t>(packet[0]);
  if (!is_known_type(type) || is_type(type, MessageType::kSealed)) {
    drop(channel, packet, wire_error(DropReason::kUnknownType, "type"), now);
    return;
  }
  if (channel != channel_of(type)) {
    drop(channel, packet, wire_error(DropReason::kWrongChannel, "channel"), now);
    return;
  }
  const bool handshake = status_.state == SessionState::kHandshake;
  const bool joiner = !is_host();
  const auto heard = [&] { status_.last_heard = now; };
  // Each kind with the states that accept it (docs/protocol.md §6, "What each state accepts").
  switch (static_cast<MessageType>(type)) {
    case MessageType::kWelcome:
      return accept<Welcome>(channel, packet, joiner && handshake && !welcome_seen_, now,
                             [&](Welcome&& m) {
                               heard();
                               on_welcome(m, now);
                             });
    case MessageType::kAccept:
      return accept<Accept>(channel, packet, joiner && handshake && join_sent_, now,
                            [&](Accept&& m) {
                              heard();
                              on_accept(m, now);
                            });
    case MessageType::kJoin:  // never: a host's joins come from strangers (on_stranger_packet)
      return accept<Join>(channel, packet, false, now, [](Join&&) {});
    case MessageType::kHello:
      return accept<Hello>(channel, packet, serving(), now, [&](Hello&& m) {
        heard();
        on_hello(std::move(m), now);
      });
    case MessageType::kTargetMap:
      return accept<TargetMap>(channel, packet, serving(), now, [&](TargetMap&& m) {
        heard();
        remote_map_ = std::move(m);
        ++stats_.target_maps_received;
      });
    case MessageType::kHeartbeat:
      return accept<Heartbeat>(channel, packet, serving(), now, [&](Heartbeat&&) { heard(); });
    case MessageType::kBye:
      return accept<Bye>(channel, packet, connected(), now, [&](Bye&& m) { on_bye(m, now); });
    case MessageType::kAvatarRequest:
      return accept<AvatarRequest>(channel, packet, serving(), now, [&](AvatarRequest&& m) {
        heard();
        on_avatar_request(m, channel, packet, now);
      });
    case MessageType::kAvatarData:
      return accept<AvatarData>(channel, packet, serving(), now, [&](AvatarData&& m) {
        heard();
        on_avatar_data(m, channel, packet, now);
      });
    case MessageType::kTracking:  // streaming only, into a preallocated message (on_tracking)
      return on_tracking(channel, packet, now);
    case MessageType::kSealed:  // dropped above
      return;
  }
}

void Session::on_tracking(Channel channel, std::span<const std::byte> packet, double now) {
  if (status_.state != SessionState::kStreaming || !remote_hello_) {
    drop(channel, packet, wire_error(DropReason::kNotStreaming, "state"), now);
    return;
  }
  const Vec3& root = remote_hello_->avatar.body.T_world_root.translation;
  if (WireResult e = decode_tracking(packet, root, tracking_rx_); !e.ok()) {
    drop(channel, packet, e, now);
    return;
  }
  status_.last_heard = now;
  ++stats_.tracking_received;
  jitter_.push(tracking_rx_.sequence, tracking_rx_.frame, now);
}

// ---------------------------------------------------------------- avatar files

std::optional<AvatarHash> Session::remote_avatar_hash() const {
  return remote_hello_ ? parse_avatar_hash(remote_hello_->avatar.model) : std::nullopt;
}

bool Session::request_avatar() {
  const std::optional<AvatarHash> hash = remote_avatar_hash();
  if (!hash || !serving()) {
    return false;
  }
  std::array<std::byte, kAvatarRequestBytes> bytes{};
  encode(AvatarRequest{*hash}, bytes);
  avatar_rx_.expect(*hash);
  log().info("net: asking {} for their avatar file {}", peer_name(), to_hex(*hash).substr(0, 12));
  return send_reliable(bytes);
}

void Session::on_avatar_request(const AvatarRequest& m, Channel channel,
                                std::span<const std::byte> packet, double now) {
  // One transfer per connection: the sender keys it by a constant, the connection being the
  // session's one served peer.
  if (!avatar_tx_.on_request(0, m.hash, now)) {
    drop(channel, packet, wire_error(DropReason::kUnexpected, "avatar_request.hash"), now);
    return;
  }
  ++stats_.avatar_requests_received;
}

void Session::on_avatar_data(const AvatarData& m, Channel channel,
                             std::span<const std::byte> packet, double now) {
  const AvatarReceiveStatus before = avatar_rx_.status();
  if (!avatar_rx_.on_data(m)) {
    drop(channel, packet, wire_error(DropReason::kUnexpected, "avatar_data.hash"), now);
    return;
  }
  ++stats_.avatar_chunks_received;
  if (before != AvatarReceiveStatus::kFailed &&
      avatar_rx_.status() == AvatarReceiveStatus::kFailed) {
    log().warn("net: the avatar file from {} was abandoned: {}", peer_name(), avatar_rx_.failure());
  }
}

void Session::send_avatar_chunks(double now) {
  if (!avatar_tx_.has_file() || status_.state != SessionState::kStreaming) {
    return;
  }
  // A few chunks at most per call; the sender's pace decides when each is due.
  for (int i = 0; i < 4; ++i) {
    const std::optional<AvatarData> chunk = avatar_tx_.next_chunk(0, now);
    if (!chunk) {
      return;
    }
    const std::size_t n = encode(*chunk, avatar_chunk_tx_);
    if (n == 0 || !send_reliable(std::span(avatar_chunk_tx_).first(n))) {
      avatar_tx_.forget(0);
      return;
    }
    ++stats_.avatar_chunks_sent;
  }
}

// ---------------------------------------------------------------- joiner's handshake

void Session::on_welcome(const Welcome& m, double now) {
  welcome_seen_ = true;
  welcome_ = m;
  if (m.auth == AuthMode::kPassphrase && !has_passphrase()) {
    return refuse(ByeReason::kPassphraseRequired, now);
  }
  if (m.auth == AuthMode::kOpen && has_passphrase()) {
    return refuse(ByeReason::kPassphraseUnexpected, now);
  }
  if (has_passphrase()) {
    // A fake host could ask for a cheap key and test guesses against our proof offline.
    if (!at_least(m.kdf, config_.min_kdf)) {
      log().error("net: {} asks for a passphrase key cost of {}, below the {} this site accepts",
                  peer_name(), cost_text(m.kdf), cost_text(config_.min_kdf));
      return refuse(ByeReason::kWeakKeyCost, now);
    }
    exchange_keys_ = make_exchange_keys();
    // Argon2id is slow on purpose: off this thread, and a reconnect to the same host reuses it.
    if (!key_.master || key_.salt != m.salt || !(key_.cost == m.kdf)) {
      // A derivation already running for this salt and cost (an attempt that ended before it was
      // done) is waited for, not restarted: restarting would block this thread on the old one.
      const bool running =
          derivation_.started() && derivation_.salt() == m.salt && derivation_.cost() == m.kdf;
      key_ = HostKey{m.salt, m.kdf, std::nullopt};
      if (!running) {
        derivation_.start(config_.passphrase, m.salt, m.kdf, config_.derive_on_this_thread);
      }
      if (!derivation_.ready()) {
        return;  // timers() sends the join when the key is there
      }
    }
  }
  send_join(now);
}

void Session::send_join(double now) {
  if (derivation_.ready()) {
    std::optional<Key> master = derivation_.take();
    if (!master) {
      log().error("net: cannot derive the passphrase key ({}): Argon2id ran out of memory?",
                  cost_text(welcome_.kdf));
      return refuse(ByeReason::kProtocolError, now);
    }
    key_.master = master;
    wipe(*master);
  }
  Join join;
  join.auth = welcome_.auth;
  random_bytes(join.joiner_challenge);
  if (has_passphrase()) {
    join.joiner_key = exchange_keys_->public_key;
    const Key transcript = transcript_of(welcome_, join);
    std::optional<Key> prk =
        handshake_secret(*key_.master, transcript, *exchange_keys_, welcome_.host_key, false);
    if (!prk) {
      return refuse(ByeReason::kProtocolError, now);  // the host's key is unusable
    }
    join.proof = seal_join_proof(*prk, transcript, config_.hello.site);
    wipe(*prk);
  }
  join_sent_ = true;
  welcome_join_ = join;
  encode(join, scratch_);
  send_reliable(scratch_);
}

void Session::on_accept(const Accept& m, double now) {
  if (has_passphrase()) {
    const Key transcript = transcript_of(welcome_, welcome_join_);
    std::optional<Key> prk =
        handshake_secret(*key_.master, transcript, *exchange_keys_, welcome_.host_key, false);
    std::optional<std::string> host_site;
    if (prk) {
      host_site = open_accept_proof(*prk, transcript, config_.hello.site, m.proof);
    }
    if (!host_site) {
      // The host does not know the passphrase: it gets nothing from us.
      if (prk) {
        wipe(*prk);
      }
      return refuse(ByeReason::kAuthenticationFailed, now);
    }
    peer_site_ = *host_site;
    authenticated(*prk, config_.hello.site, *host_site);
    wipe(*prk);
  }
  enter_hello(now);
}

void Session::on_hello(Hello&& m, double now) {
  if (!peer_site_.empty() && m.site != peer_site_) {
    // The proof bound the peer's site name: a hello under another one breaks the handshake.
    log().warn("net: {} proved site '{}' but says hello as '{}'", peer_name(), peer_site_, m.site);
    return refuse(ByeReason::kProtocolError, now);
  }
  remote_hello_ = std::move(m);
  ++status_.hellos;
  if (status_.state == SessionState::kHello) {
    status_.state = SessionState::kStreaming;
    ++status_.streams;
    reconnect_delay_ = config_.reconnect_min;
    jitter_.reset();
    log().info("net: {} streaming with {} ({}){}", config_.hello.site, remote_hello_->site,
               peer_name(), sealer_ ? ", sealed" : "");
  }
}

void Session::on_bye(const Bye& m, double now) {
  status_.last_bye = m.reason;
  log().info("net: {} said bye: {}", peer_name(), bye_reason_name(m.reason));
  link_.disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kLeaving));
  end_connection(EndCause::kByeFromPeer, now);
  if (!is_host() && is_refusal(m.reason)) {
    status_.state = SessionState::kRefused;
  }
}

}  // namespace deixis::net
