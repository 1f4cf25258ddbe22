#include "net/session.h"

#include <sodium.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <bit>

#include "gesture/error.h"
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
  }
  return "?";
}

namespace {

// A sealed packet needs room for the inner packet and the overhead.
constexpr std::size_t kSealedBufferBytes = kMaxPacketBytes + kSealOverheadBytes;

std::string wire_message(std::string_view what, WireResult why) {
  return std::string(what) + ": " + why.field + ": " + std::string(drop_reason_name(why.reason));
}

// A packet's expected channel.
Channel channel_of(std::uint8_t type) {
  return type == static_cast<std::uint8_t>(MessageType::kTracking) ? Channel::kTracking
                                                                   : Channel::kReliable;
}

}  // namespace

Session::Session(Link& link, SessionConfig config)
    : link_(link),
      config_(std::move(config)),
      drop_log_(config_.logger),
      jitter_(config_.jitter),
      sealed_tx_(kSealedBufferBytes),
      plain_rx_(kMaxPacketBytes) {
  if (WireResult e = encode(config_.hello, hello_bytes_); !e.ok()) {
    throw Error(wire_message("session: our hello", e));
  }
  if (WireResult e = encode(config_.target_map, map_bytes_); !e.ok()) {
    throw Error(wire_message("session: our target map", e));
  }
  if (!sodium_ready()) {
    throw Error("session: libsodium failed to initialise");
  }
  reconnect_delay_ = config_.reconnect_min;
  if (config_.role == Role::kHost && has_passphrase()) {
    // One salt and key per hosting session: a joiner that reconnects reuses its derived key.
    random_bytes(salt_);
    key_cost_ = config_.kdf;
    master_key_ = derive_master_key(config_.passphrase, salt_, key_cost_);
    if (!master_key_) {
      throw Error("session: cannot derive the passphrase key (Argon2id ran out of memory?)");
    }
  }
}

Session::~Session() {
  if (master_key_) {
    sodium_memzero(master_key_->data(), master_key_->size());
  }
}

spdlog::logger& Session::log() const {
  return config_.logger ? *config_.logger : *spdlog::default_logger_raw();
}

bool Session::connected() const {
  return status_.state == SessionState::kHandshake || status_.state == SessionState::kHello ||
         status_.state == SessionState::kStreaming;
}

// ---------------------------------------------------------------- driving

void Session::start(double now) {
  status_.last_heard = now;
  if (config_.role == Role::kHost) {
    status_.state = SessionState::kWaiting;
    log().info("net: {} listening", config_.hello.site);
    return;
  }
  attempt(now);
}

void Session::service(double now, std::uint32_t wait_ms) {
  for (LinkEvent e = link_.next_event(wait_ms); e.kind != LinkEvent::Kind::kNone;
       e = link_.next_event(0)) {
    switch (e.kind) {
      case LinkEvent::Kind::kConnected:
        on_connected(now);
        break;
      case LinkEvent::Kind::kDisconnected:
        on_disconnected(e.data, now);
        break;
      case LinkEvent::Kind::kReceived:
        on_packet(e.channel, e.bytes, now);
        break;
      case LinkEvent::Kind::kNone:
        break;
    }
  }
  timers(now);
  status_.round_trip_ms = link_.round_trip_ms();
}

void Session::timers(double now) {
  switch (status_.state) {
    case SessionState::kWaiting:
      if (config_.role == Role::kJoiner && now >= status_.next_attempt) {
        attempt(now);
      }
      break;
    case SessionState::kConnecting:
      if (now >= deadline_) {
        link_.disconnect(0);
        end_connection(EndCause::kConnectFailed, now);
      }
      break;
    case SessionState::kHandshake:
      if (now >= deadline_) {
        log().warn("net: handshake with {} did not finish in {:.1f} s", link_.peer_name(),
                   config_.handshake_timeout);
        send_bye(ByeReason::kProtocolError);
        link_.disconnect(static_cast<std::uint32_t>(ByeReason::kProtocolError));
        end_connection(EndCause::kHandshakeTimedOut, now);
      }
      break;
    case SessionState::kHello:
    case SessionState::kStreaming:
      if (now - status_.last_heard > config_.heartbeat_timeout) {
        ++status_.timeouts;
        log().warn("net: {} timed out: nothing heard for {:.1f} s", link_.peer_name(),
                   now - status_.last_heard);
        link_.disconnect(static_cast<std::uint32_t>(ByeReason::kLeaving));
        end_connection(EndCause::kTimedOut, now);
      } else if (now >= next_heartbeat_) {
        std::array<std::byte, kHeartbeatBytes> bytes{};
        encode(Heartbeat{heartbeats_sent_++}, bytes);
        send_reliable(bytes);
        next_heartbeat_ = now + config_.heartbeat_interval;
      }
      break;
    case SessionState::kIdle:
    case SessionState::kRefused:
      break;
  }
}

void Session::attempt(double now) {
  ++status_.attempts;
  if (!link_.connect()) {
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
  if (!link_.send(Channel::kTracking, packet)) {
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

void Session::set_target_map(const TargetMap& map) {
  std::vector<std::byte> bytes;
  if (WireResult e = encode(map, bytes); !e.ok()) {
    throw Error(wire_message("session: target map", e));
  }
  config_.target_map = map;
  map_bytes_ = std::move(bytes);
  if (status_.state == SessionState::kHello || status_.state == SessionState::kStreaming) {
    send_reliable(map_bytes_);
  }
}

void Session::close(double now) {
  if (connected()) {
    send_bye(ByeReason::kLeaving);
    link_.disconnect(static_cast<std::uint32_t>(ByeReason::kLeaving));
  } else if (status_.state == SessionState::kConnecting) {
    link_.disconnect(0);
  }
  end_connection(EndCause::kClosed, now);
  status_.state = SessionState::kIdle;
}

// ---------------------------------------------------------------- sending

bool Session::send_reliable(std::span<const std::byte> packet) {
  std::span<const std::byte> out = packet;
  if (sealer_) {
    const std::size_t size = sealer_->seal(Channel::kReliable, packet, sealed_tx_);
    if (size == 0) {
      ++stats_.send_failures;
      return false;
    }
    out = std::span(sealed_tx_).first(size);
  }
  if (!link_.send(Channel::kReliable, out)) {
    ++stats_.send_failures;
    return false;
  }
  ++stats_.packets_sent;
  stats_.bytes_sent += out.size();
  return true;
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

void Session::begin_connection(double now) {
  status_.state = SessionState::kHandshake;
  status_.last_heard = now;
  deadline_ = now + config_.handshake_timeout;
  welcome_seen_ = false;
  join_seen_ = false;
  sealer_.reset();
  opener_.reset();
  heartbeats_sent_ = 0;
  tracking_sequence_ = 0;
  remote_hello_.reset();
  remote_map_.reset();
  jitter_.reset();
}

void Session::on_connected(double now) {
  if (connected()) {
    // The transport replaced the connection under us: start over with the new one.
    end_connection(EndCause::kTransportLost, now);
  }
  if (config_.role == Role::kJoiner && status_.state != SessionState::kConnecting) {
    link_.disconnect(0);  // a connection we no longer wanted (closed or refused meanwhile)
    return;
  }
  if (config_.role == Role::kHost && status_.state != SessionState::kWaiting) {
    link_.disconnect(static_cast<std::uint32_t>(ByeReason::kBusy));
    return;
  }
  if (config_.role == Role::kHost) {
    ++status_.attempts;
  }
  begin_connection(now);
  log().info("net: {} connected to {}", config_.hello.site, link_.peer_name());
  if (config_.role == Role::kHost) {
    random_bytes(host_challenge_);
    Welcome w;
    w.auth = has_passphrase() ? AuthMode::kPassphrase : AuthMode::kOpen;
    if (has_passphrase()) {
      w.salt = salt_;
      w.kdf = key_cost_;
    }
    w.host_challenge = host_challenge_;
    encode(w, scratch_);
    send_reliable(scratch_);
  }
}

void Session::on_disconnected(std::uint32_t code, double now) {
  if (!connected() && status_.state != SessionState::kConnecting) {
    return;
  }
  const bool was_connecting = status_.state == SessionState::kConnecting;
  if (code <= kMaxByeReason && code != 0) {
    const auto reason = static_cast<ByeReason>(code);
    status_.last_bye = reason;
    if (config_.role == Role::kJoiner && is_refusal(reason)) {
      log().warn("net: {} refused us: {}", link_.peer_name(), bye_reason_name(reason));
      end_connection(EndCause::kByeFromPeer, now);
      status_.state = SessionState::kRefused;
      return;
    }
  }
  if (!was_connecting) {
    log().info("net: {} disconnected", link_.peer_name());
  }
  end_connection(was_connecting ? EndCause::kConnectFailed : EndCause::kTransportLost, now);
}

void Session::authenticated(const Key& master) {
  const SessionKeys keys =
      derive_session_keys(master, host_challenge_, joiner_challenge_, config_.role == Role::kHost);
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
  log().warn("net: refusing {}: {}", link_.peer_name(), bye_reason_name(reason));
  send_bye(reason);
  link_.disconnect(static_cast<std::uint32_t>(reason));
  status_.last_bye = reason;
  if (reason == ByeReason::kAuthenticationFailed) {
    ++status_.auth_failures;
  }
  end_connection(EndCause::kRefusedPeer, now);
  // A joiner cannot fix a refusal by retrying; a host listens for the next peer.
  if (config_.role == Role::kJoiner && is_refusal(reason)) {
    status_.state = SessionState::kRefused;
  }
}

void Session::end_connection(EndCause cause, double now) {
  status_.last_end = cause;
  sealer_.reset();
  opener_.reset();
  jitter_.reset();
  if (config_.role == Role::kHost) {
    status_.state = SessionState::kWaiting;
  } else {
    schedule_attempt(now);
  }
}

// ---------------------------------------------------------------- receiving

void Session::drop(Channel channel, std::span<const std::byte> packet, WireResult why, double now) {
  const int type = packet.empty() ? kNoType : std::to_integer<int>(packet[0]);
  drop_log_.drop(now, link_.peer_name(), channel, type, why);
}

void Session::on_packet(Channel channel, std::span<const std::byte> bytes, double now) {
  ++stats_.packets_received;
  stats_.bytes_received += bytes.size();
  if (bytes.empty()) {
    drop(channel, bytes, wire_error(DropReason::kEmpty, "packet"), now);
    return;
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  const bool is_sealed = type == static_cast<std::uint8_t>(MessageType::kSealed);
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
    if (inner.empty() || inner[0] == static_cast<std::byte>(MessageType::kSealed)) {
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
  const bool handshake_message = type == static_cast<std::uint8_t>(MessageType::kWelcome) ||
                                 type == static_cast<std::uint8_t>(MessageType::kJoin) ||
                                 type == static_cast<std::uint8_t>(MessageType::kAccept) ||
                                 type == static_cast<std::uint8_t>(MessageType::kBye);
  if (has_passphrase() && is_known_type(type) && !handshake_message) {
    drop(channel, bytes, wire_error(DropReason::kUnauthenticated, "packet"), now);
    return;
  }
  dispatch(channel, bytes, now);
}

void Session::dispatch(Channel channel, std::span<const std::byte> packet, double now) {
  const auto type = std::to_integer<std::uint8_t>(packet[0]);
  if (!is_known_type(type) || type == static_cast<std::uint8_t>(MessageType::kSealed)) {
    drop(channel, packet, wire_error(DropReason::kUnknownType, "type"), now);
    return;
  }
  if (channel != channel_of(type)) {
    drop(channel, packet, wire_error(DropReason::kWrongChannel, "channel"), now);
    return;
  }
  const auto unexpected = [&] {
    drop(channel, packet, wire_error(DropReason::kUnexpected, "state"), now);
  };
  const bool in_hello_or_streaming =
      status_.state == SessionState::kHello || status_.state == SessionState::kStreaming;
  WireResult result;
  switch (static_cast<MessageType>(type)) {
    case MessageType::kWelcome: {
      if (config_.role != Role::kJoiner || status_.state != SessionState::kHandshake ||
          welcome_seen_) {
        return unexpected();
      }
      Welcome m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        on_welcome(m, now);
        return;
      }
      break;
    }
    case MessageType::kJoin: {
      if (config_.role != Role::kHost || status_.state != SessionState::kHandshake || join_seen_) {
        return unexpected();
      }
      Join m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        on_join(m, now);
        return;
      }
      break;
    }
    case MessageType::kAccept: {
      if (config_.role != Role::kJoiner || status_.state != SessionState::kHandshake ||
          !welcome_seen_) {
        return unexpected();
      }
      Accept m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        on_accept(m, now);
        return;
      }
      break;
    }
    case MessageType::kHello: {
      if (!in_hello_or_streaming) {
        return unexpected();
      }
      Hello m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        on_hello(std::move(m));
        return;
      }
      break;
    }
    case MessageType::kTargetMap: {
      if (!in_hello_or_streaming) {
        return unexpected();
      }
      TargetMap m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        remote_map_ = std::move(m);
        ++stats_.target_maps_received;
        return;
      }
      break;
    }
    case MessageType::kHeartbeat: {
      if (!in_hello_or_streaming) {
        return unexpected();
      }
      Heartbeat m;
      result = decode(packet, m);
      if (result.ok()) {
        status_.last_heard = now;
        return;
      }
      break;
    }
    case MessageType::kBye: {
      if (!connected()) {
        return unexpected();
      }
      Bye m;
      result = decode(packet, m);
      if (result.ok()) {
        on_bye(m, now);
        return;
      }
      break;
    }
    case MessageType::kTracking:
      on_tracking(channel, packet, now);
      return;
    case MessageType::kSealed:
      break;
  }
  drop(channel, packet, result, now);
  // A peer speaking another protocol version gets told so, rather than waiting out a time-out.
  if (result.reason == DropReason::kWrongVersion && status_.state == SessionState::kHandshake) {
    refuse(ByeReason::kVersionMismatch, now);
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

void Session::on_welcome(const Welcome& m, double now) {
  welcome_seen_ = true;
  host_challenge_ = m.host_challenge;
  if (m.auth == AuthMode::kPassphrase && !has_passphrase()) {
    return refuse(ByeReason::kPassphraseRequired, now);
  }
  if (m.auth == AuthMode::kOpen && has_passphrase()) {
    return refuse(ByeReason::kPassphraseUnexpected, now);
  }
  random_bytes(joiner_challenge_);
  Join join;
  join.auth = m.auth;
  join.joiner_challenge = joiner_challenge_;
  if (has_passphrase()) {
    // Argon2id is slow on purpose; a reconnect to the same host reuses the key.
    if (!master_key_ || salt_ != m.salt || !(key_cost_ == m.kdf)) {
      salt_ = m.salt;
      key_cost_ = m.kdf;
      master_key_ = derive_master_key(config_.passphrase, salt_, key_cost_);
    }
    if (!master_key_) {
      log().error("net: cannot derive the passphrase key (cost {} / {} KiB)", m.kdf.opslimit,
                  m.kdf.memlimit_kib);
      send_bye(ByeReason::kProtocolError);
      link_.disconnect(static_cast<std::uint32_t>(ByeReason::kProtocolError));
      return end_connection(EndCause::kRefusedPeer, now);
    }
    join.proof = join_proof(*master_key_, salt_, host_challenge_, joiner_challenge_);
  }
  encode(join, scratch_);
  send_reliable(scratch_);
}

void Session::on_join(const Join& m, double now) {
  join_seen_ = true;
  joiner_challenge_ = m.joiner_challenge;
  if (has_passphrase() && m.auth != AuthMode::kPassphrase) {
    return refuse(ByeReason::kPassphraseRequired, now);
  }
  if (!has_passphrase() && m.auth != AuthMode::kOpen) {
    return refuse(ByeReason::kPassphraseUnexpected, now);
  }
  Accept accept;
  if (has_passphrase()) {
    const Proof expected = join_proof(*master_key_, salt_, host_challenge_, joiner_challenge_);
    if (!proofs_equal(expected, m.proof)) {
      return refuse(ByeReason::kAuthenticationFailed, now);
    }
    accept.proof = accept_proof(*master_key_, salt_, host_challenge_, joiner_challenge_);
  }
  encode(accept, scratch_);
  send_reliable(scratch_);  // plain: the joiner needs it to check us and derive the keys
  if (has_passphrase()) {
    authenticated(*master_key_);
  }
  enter_hello(now);
}

void Session::on_accept(const Accept& m, double now) {
  if (has_passphrase()) {
    const Proof expected = accept_proof(*master_key_, salt_, host_challenge_, joiner_challenge_);
    if (!proofs_equal(expected, m.proof)) {
      // The host does not know the passphrase: it gets nothing from us.
      return refuse(ByeReason::kAuthenticationFailed, now);
    }
    authenticated(*master_key_);
  }
  enter_hello(now);
}

void Session::on_hello(Hello&& m) {
  remote_hello_ = std::move(m);
  if (status_.state == SessionState::kHello) {
    status_.state = SessionState::kStreaming;
    ++status_.streams;
    reconnect_delay_ = config_.reconnect_min;
    jitter_.reset();
    log().info("net: {} streaming with {} ({}){}", config_.hello.site, remote_hello_->site,
               link_.peer_name(), sealer_ ? ", sealed" : "");
  }
}

void Session::on_bye(const Bye& m, double now) {
  status_.last_bye = m.reason;
  log().info("net: {} said bye: {}", link_.peer_name(), bye_reason_name(m.reason));
  link_.disconnect(static_cast<std::uint32_t>(ByeReason::kLeaving));
  end_connection(EndCause::kByeFromPeer, now);
  if (config_.role == Role::kJoiner && is_refusal(m.reason)) {
    status_.state = SessionState::kRefused;
  }
}

}  // namespace deixis::net
