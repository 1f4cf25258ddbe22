#include "net/relay_client.h"

#include <sodium.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "core/error.h"
#include "net/enet_link.h"
#include "net/relay_wire.h"

namespace deixis::net {

namespace {

// ENet's own time-out, above our silence time-out so that ours fires first.
constexpr std::uint32_t kEnetTimeoutMs = 3000;
constexpr std::uint32_t kCloseDrainMs = 500;

bool looks_like_direct_welcome(std::span<const std::byte> bytes) {
  return bytes.size() >= 1 + kMagic.size() &&
         std::to_integer<std::uint8_t>(bytes[0]) ==
             static_cast<std::uint8_t>(MessageType::kWelcome) &&
         std::equal(kMagic.begin(), kMagic.end(), bytes.begin() + 1);
}

}  // namespace

RoomToken room_token(std::string_view room_name) {
  static constexpr std::string_view kDomain = "deixis room";
  RoomToken token{};
  if (sodium_init() < 0) {
    throw Error("libsodium could not be initialised");
  }
  crypto_generichash_state state;
  crypto_generichash_init(&state, nullptr, 0, token.size());
  crypto_generichash_update(&state, reinterpret_cast<const unsigned char*>(kDomain.data()),
                            kDomain.size());
  crypto_generichash_update(&state, reinterpret_cast<const unsigned char*>(room_name.data()),
                            room_name.size());
  crypto_generichash_final(&state, token.data(), token.size());
  return token;
}

std::string_view describe(RelayRefusal why) {
  switch (why) {
    case RelayRefusal::kRoomFull:
      return "the room is full (the relay's --max-people)";
    case RelayRefusal::kRelayFull:
      return "the relay is full (too many rooms or connections): try later";
    case RelayRefusal::kVersion:
      return "the relay speaks another relay protocol version";
    case RelayRefusal::kTryLater:
      return "too many connections from this address: try later";
    case RelayRefusal::kProtocol:
      return "relay protocol error";
    case RelayRefusal::kFlooding:
      return "sent more than the relay's packet budget";
    case RelayRefusal::kNotARelay:
      return "not a relay: the address answers as a direct-session host (use join without --room)";
  }
  return "unknown refusal";
}

bool is_final(RelayRefusal why) {
  return why == RelayRefusal::kRoomFull || why == RelayRefusal::kVersion ||
         why == RelayRefusal::kNotARelay;
}

RelayClient::RelayClient(const RelayClientOptions& options, double now)
    : options_(options),
      link_(EnetLink::join(options.host, options.port, options.local_address)),
      drop_log_(options.logger),
      tx_(kRelayForwardHeaderBytes + kRelayPayloadMax) {
  link_->set_timeout_ms(kEnetTimeoutMs);
  attempt(now);
}

RelayClient::~RelayClient() = default;

spdlog::logger& RelayClient::log() const {
  return options_.logger ? *options_.logger : *spdlog::default_logger_raw();
}

std::uint16_t RelayClient::local_port() const {
  return link_->port();
}

std::uint32_t RelayClient::round_trip_ms() const {
  return connected_ && peer_ != kNoPeer ? link_->round_trip_ms(peer_) : 0;
}

void RelayClient::attempt(double now) {
  ++stats_.attempts;
  connected_ = false;
  welcomed_ = false;
  entering_ = false;
  in_room_ = false;
  self_ = kNoMember;
  peer_ = link_->connect();
  deadline_ = now + kRelayConnectTimeout;
  if (peer_ == kNoPeer) {
    schedule(now);
  }
}

void RelayClient::schedule(double now) {
  peer_ = kNoPeer;
  next_attempt_ = now + backoff_;
  backoff_ = std::min(backoff_ * 2.0, kRelayReconnectMax);
}

void RelayClient::poll(double now, RelayListener& listener, std::uint32_t wait_ms) {
  for (std::size_t i = 0; i < kMaxEventsPerPoll; ++i) {
    const LinkEvent e = link_->next_event(i == 0 ? wait_ms : 0);
    if (e.kind == LinkEvent::Kind::kNone) {
      break;
    }
    on_event(e, now, listener);
  }
  if (stopped_) {
    return;
  }
  if (peer_ == kNoPeer) {
    if (now >= next_attempt_) {
      attempt(now);
    }
    return;
  }
  if (!welcomed_) {
    if (now >= deadline_) {  // no connection or no welcome in time: try again
      link_->disconnect(peer_, 0);
      schedule(now);
    }
    return;
  }
  if (!entering_ && !in_room_) {
    last_heard_ = now;  // the relay waits for our enter (3 s at most) and sends nothing meanwhile
  }
  if (now - last_heard_ > kRelaySilenceTimeout) {
    return lost(now, listener, "the relay fell silent");
  }
  if (now >= next_keepalive_) {
    std::array<std::byte, kRelayKeepaliveBytes> k{};
    send_reliable(std::span(k).first(encode_keepalive(k)));
    next_keepalive_ = now + kRelayKeepaliveInterval;
  }
}

void RelayClient::on_event(const LinkEvent& e, double now, RelayListener& listener) {
  if (e.peer != peer_ || peer_ == kNoPeer || stopped_) {
    return;  // an earlier attempt's, or after close()
  }
  switch (e.kind) {
    case LinkEvent::Kind::kConnected:
      connected_ = true;
      last_heard_ = now;
      return;
    case LinkEvent::Kind::kDisconnected:
      if (welcomed_) {
        return lost(now, listener, "the relay closed the connection");
      }
      schedule(now);
      return;
    case LinkEvent::Kind::kReceived:
      return on_packet(e.channel, e.bytes, now, listener);
    case LinkEvent::Kind::kNone:
      return;
  }
}

void RelayClient::lost(double now, RelayListener& listener, const char* why) {
  const bool was_welcomed = welcomed_;
  if (warn_budget_.take(now)) {
    log().warn("relay: {}:{} lost: {}", options_.host, options_.port, why);
  }
  if (peer_ != kNoPeer) {
    link_->disconnect(peer_, 0);
  }
  welcomed_ = false;
  entering_ = false;
  in_room_ = false;
  self_ = kNoMember;
  schedule(now);
  if (was_welcomed) {
    ++stats_.relay_lost;
    listener.on_relay_lost();
  }
}

void RelayClient::stop(RelayRefusal why, double now, RelayListener& listener) {
  log().warn("relay: {}:{} refused us: {}", options_.host, options_.port, describe(why));
  if (peer_ != kNoPeer) {
    // A direct host hears "another version" and lets us go at once.
    link_->disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kVersionMismatch));
  }
  const bool was_welcomed = welcomed_;
  peer_ = kNoPeer;
  welcomed_ = false;
  entering_ = false;
  in_room_ = false;
  self_ = kNoMember;
  stopped_ = true;
  listener.on_refused(why);
  if (was_welcomed) {
    ++stats_.relay_lost;
    listener.on_relay_lost();
  }
  (void)now;
}

void RelayClient::on_packet(Channel channel, std::span<const std::byte> bytes, double now,
                            RelayListener& listener) {
  const std::string_view peer = link_->peer_name(peer_);
  if (bytes.empty()) {
    return drop_log_.drop(now, peer, channel, kNoType, wire_error(DropReason::kEmpty, "packet"));
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  if (!is_relay_type(type)) {
    if (!welcomed_ && looks_like_direct_welcome(bytes)) {
      ++stats_.refusals;
      return stop(RelayRefusal::kNotARelay, now, listener);
    }
    return drop_log_.drop(now, peer, channel, type, wire_error(DropReason::kUnknownType, "type"));
  }
  if (!relay_channel_allowed(type, channel)) {
    return drop_log_.drop(now, peer, channel, type,
                          wire_error(DropReason::kWrongChannel, "channel"));
  }
  const auto unexpected = [&] {
    drop_log_.drop(now, peer, channel, type, wire_error(DropReason::kUnexpected, "state"));
  };
  const auto bad = [&](WireResult e) { drop_log_.drop(now, peer, channel, type, e); };
  // A message of the room through its decoder to `use`, if the client's state allows it now.
  const auto accept = [&](auto message, bool allowed, auto&& use) {
    if (!allowed) {
      return unexpected();
    }
    if (const WireResult e = decode(bytes, message); !e.ok()) {
      return bad(e);
    }
    last_heard_ = now;
    use(message);
  };
  switch (static_cast<RelayType>(type)) {
    case RelayType::kWelcome: {
      if (welcomed_) {
        return unexpected();
      }
      RelayWelcome m;
      if (const WireResult e = decode(bytes, m); !e.ok()) {
        bad(e);
        if (e.reason == DropReason::kWrongVersion) {
          ++stats_.refusals;
          stop(RelayRefusal::kVersion, now, listener);
        }
        return;
      }
      welcomed_ = true;
      last_heard_ = now;
      next_keepalive_ = now + kRelayKeepaliveInterval;
      backoff_ = kRelayReconnectMin;
      ++stats_.welcomes;
      return listener.on_relay_ready();
    }
    case RelayType::kEntered:
      return accept(RelayEntered{}, entering_ && !in_room_, [&](const RelayEntered& m) {
        entering_ = false;
        in_room_ = true;
        self_ = m.self;
        ++stats_.entries;
        listener.on_entered(m.self, m.params, std::span(m.members).first(m.count));
      });
    case RelayType::kJoined:
      return accept(RelayJoined{}, in_room_,
                    [&](const RelayJoined& m) { listener.on_member_joined(m.member); });
    case RelayType::kLeft:
      return accept(RelayLeft{}, in_room_,
                    [&](const RelayLeft& m) { listener.on_member_left(m.id); });
    case RelayType::kRefused: {
      RelayRefused m;
      if (const WireResult e = decode(bytes, m); !e.ok()) {
        return bad(e);
      }
      ++stats_.refusals;
      if (is_final(m.reason)) {
        return stop(m.reason, now, listener);
      }
      if (warn_budget_.take(now)) {
        log().warn("relay: {}:{} turned us away: {}", options_.host, options_.port,
                   describe(m.reason));
      }
      listener.on_refused(m.reason);
      if (m.reason == RelayRefusal::kFlooding) {
        backoff_ = kRelayReconnectMax;
      }
      return lost(now, listener, "refused");
    }
    case RelayType::kForwarded:
      return accept(RelayForwarded{}, in_room_, [&](const RelayForwarded& m) {
        ++stats_.received;
        stats_.bytes_received += m.payload.size();
        listener.on_payload(m.from, channel, as_u8(m.payload));
      });
    case RelayType::kKeepalive:
      if (const WireResult e = decode_keepalive(bytes); !e.ok()) {
        return bad(e);
      }
      last_heard_ = now;
      return;
    case RelayType::kEnter:
    case RelayType::kForward:
      return unexpected();
  }
}

bool RelayClient::send_reliable(std::span<const std::byte> packet) {
  return peer_ != kNoPeer && !packet.empty() && link_->send(peer_, Channel::kReliable, packet);
}

bool RelayClient::enter(std::span<const std::uint8_t> room_params,
                        std::span<const std::uint8_t> announce) {
  if (!welcomed_ || entering_ || in_room_ || stopped_) {
    return false;
  }
  RelayEnter m;
  m.room = options_.room;
  m.params = room_params;
  m.announce = announce;
  std::array<std::byte, kRelayEnterMaxBytes> out{};
  const std::size_t n = encode(m, out);
  if (n == 0 || !send_reliable(std::span(out).first(n))) {
    return false;
  }
  entering_ = true;
  return true;
}

bool RelayClient::send(MemberId to, Channel channel, std::span<const std::uint8_t> payload) {
  if (!in_room_) {
    return false;
  }
  const std::size_t n = encode_forward(to, as_wire(payload), tx_);
  if (n == 0 || !link_->send(peer_, channel, std::span(tx_).first(n))) {
    ++stats_.send_failures;
    return false;
  }
  ++stats_.sent;
  stats_.bytes_sent += payload.size();
  return true;
}

void RelayClient::close(double now) {
  (void)now;
  if (peer_ != kNoPeer) {
    link_->disconnect(peer_, static_cast<std::uint32_t>(ByeReason::kLeaving));
    link_->drain(kCloseDrainMs);
  }
  peer_ = kNoPeer;
  welcomed_ = false;
  entering_ = false;
  in_room_ = false;
  self_ = kNoMember;
  stopped_ = true;
}

}  // namespace deixis::net
