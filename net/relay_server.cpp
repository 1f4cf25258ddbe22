#include "net/relay_server.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <string>

#include "core/error.h"

namespace deixis::net {

namespace {

// The direct protocol's "version mismatch": a direct-session joiner that reached a relay hears it
// as a final refusal when the relay lets it go (docs/relay.md, "Telling a relay from a host").
constexpr auto kStrangerCode = static_cast<std::uint32_t>(ByeReason::kVersionMismatch);
constexpr auto kLeavingCode = static_cast<std::uint32_t>(ByeReason::kLeaving);
constexpr double kTimerPeriod = 0.05;  // s between timer sweeps

// The first four bytes of a token, for log lines: rooms are told apart, names never shown.
std::string room_label(const RoomToken& t) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < 4; ++i) {
    s += kHex[t[i] >> 4];
    s += kHex[t[i] & 15];
  }
  return s;
}

}  // namespace

RelayServer::RelayServer(Link& link, RelayServerConfig config)
    : link_(link), config_(std::move(config)), drop_log_(config_.logger) {
  if (config_.max_people < 2 || config_.max_people > kMaxRoomPeople) {
    throw Error("relay: --max-people must be 2 to " + std::to_string(kMaxRoomPeople));
  }
  if (config_.max_rooms == 0 || config_.max_connections == 0 || config_.max_pending == 0) {
    throw Error("relay: the room, connection and pending caps must be at least 1");
  }
  conns_.resize(config_.max_connections);
  conn_of_.reserve(config_.max_connections);
  free_conns_.reserve(config_.max_connections);
  for (std::size_t i = config_.max_connections; i-- > 0;) {
    free_conns_.push_back(i);
  }
  rooms_.resize(config_.max_rooms);
  tx_.resize(kMaxPacketBytes);
}

RelayServer::~RelayServer() = default;

spdlog::logger& RelayServer::log() const {
  return config_.logger ? *config_.logger : *spdlog::default_logger_raw();
}

std::size_t RelayServer::members() const {
  return conn_of_.size() - pending_count_;
}

std::size_t RelayServer::pending() const {
  return pending_count_;
}

std::size_t RelayServer::members_in(const RoomToken& room) const {
  const std::size_t r = find_room(room);
  return r < rooms_.size() ? rooms_[r].count : 0;
}

void RelayServer::service(double now, std::uint32_t wait_ms) {
  std::size_t handled = 0;
  for (; handled < config_.max_events_per_service; ++handled) {
    const LinkEvent e = link_.next_event(handled == 0 ? wait_ms : 0);
    if (e.kind == LinkEvent::Kind::kNone) {
      break;
    }
    on_event(e, now);
  }
  if (handled == config_.max_events_per_service) {
    ++stats_.service_bounded;
  }
  if (now >= next_timers_) {
    next_timers_ = now + kTimerPeriod;
    timers(now);
  }
}

void RelayServer::on_event(const LinkEvent& e, double now) {
  switch (e.kind) {
    case LinkEvent::Kind::kConnected:
      return on_connected(e.peer, now);
    case LinkEvent::Kind::kDisconnected:
      return on_disconnected(e.peer, now);
    case LinkEvent::Kind::kReceived:
      return on_packet(e.peer, e.channel, e.bytes, now);
    case LinkEvent::Kind::kNone:
      return;
  }
}

// ---------------------------------------------------------------- connections

std::size_t RelayServer::find_conn(PeerId peer) const {
  const auto it = conn_of_.find(peer);
  return it == conn_of_.end() ? conns_.size() : it->second;
}

std::size_t RelayServer::pending_from(std::uint32_t address) const {
  return static_cast<std::size_t>(std::count_if(conns_.begin(), conns_.end(), [&](const Conn& c) {
    return c.state == ConnState::kPending && c.address == address;
  }));
}

void RelayServer::on_connected(PeerId peer, double now) {
  const std::uint32_t address = link_.peer_address(peer);
  if (pending_from(address) >= config_.max_pending_per_address) {
    ++stats_.pending_over_budget;
    if (warn_budget_.take(now)) {
      log().warn("relay: turning away {}: too many connections from its address waiting to enter",
                 link_.peer_name(peer));
    }
    link_.disconnect(peer, kStrangerCode);
    return;
  }
  if (pending_count_ >= config_.max_pending) {
    evict_oldest_pending(now);
  }
  if (free_conns_.empty() || conn_of_.count(peer) != 0) {
    ++stats_.connections_full;
    if (warn_budget_.take(now)) {
      log().warn("relay: turning away {}: {} connections already", link_.peer_name(peer),
                 config_.max_connections);
    }
    link_.disconnect(peer, kStrangerCode);
    return;
  }
  const std::size_t c = free_conns_.back();
  free_conns_.pop_back();
  conns_[c] = Conn{};
  Conn& conn = conns_[c];
  conn.state = ConnState::kPending;
  conn.peer = peer;
  conn.address = address;
  conn.since = now;
  conn.last_heard = now;
  conn.last_sent = now;
  conn.budget = Bucket{config_.budget.packets_per_second * config_.budget.burst_seconds,
                       config_.budget.bytes_per_second * config_.budget.burst_seconds, now};
  conn_of_.emplace(peer, c);
  ++pending_count_;
  ++stats_.connections;
  RelayWelcome w;
  w.max_people = static_cast<std::uint8_t>(config_.max_people);
  send(c, Channel::kReliable, std::span(tx_).first(encode(w, tx_)));
}

void RelayServer::evict_oldest_pending(double now) {
  std::size_t oldest = conns_.size();
  for (std::size_t i = 0; i < conns_.size(); ++i) {
    if (conns_[i].state == ConnState::kPending &&
        (oldest == conns_.size() || conns_[i].since < conns_[oldest].since)) {
      oldest = i;
    }
  }
  if (oldest < conns_.size()) {
    ++stats_.pending_evicted;
    release(oldest, kStrangerCode, now, "evicted");
  }
}

void RelayServer::on_disconnected(PeerId peer, double now) {
  const std::size_t c = find_conn(peer);
  if (c == conns_.size()) {
    return;
  }
  // The link has forgotten the peer: nothing to disconnect.
  if (conns_[c].state == ConnState::kMember) {
    remove_member(c, now, "disconnected");
  }
  if (conns_[c].state == ConnState::kPending) {
    --pending_count_;
  }
  conn_of_.erase(peer);
  conns_[c] = Conn{};
  free_conns_.push_back(c);
}

void RelayServer::release(std::size_t c, std::uint32_t code, double now, const char* why) {
  Conn& conn = conns_[c];
  if (conn.state == ConnState::kMember) {
    remove_member(c, now, why);
  }
  if (conn.state == ConnState::kPending) {
    --pending_count_;
  }
  link_.disconnect(conn.peer, code);
  conn_of_.erase(conn.peer);
  conn = Conn{};
  free_conns_.push_back(c);
}

void RelayServer::refuse(std::size_t c, RelayRefusal why, double now) {
  RelayRefused m;
  m.reason = why;
  send(c, Channel::kReliable, std::span(tx_).first(encode(m, tx_)));
  if (warn_budget_.take(now)) {
    log().warn("relay: refusing {}: {}", link_.peer_name(conns_[c].peer), describe(why));
  }
  release(c, why == RelayRefusal::kFlooding ? kLeavingCode : kStrangerCode, now,
          describe(why).data());
}

bool RelayServer::send(std::size_t c, Channel channel, std::span<const std::byte> packet) {
  if (packet.empty() || !link_.send(conns_[c].peer, channel, packet)) {
    ++stats_.send_failures;
    return false;
  }
  return true;
}

bool RelayServer::within_budget(Conn& conn, std::size_t bytes, double now) {
  Bucket& b = conn.budget;
  const PeerBudget& budget = config_.budget;
  const double dt = std::max(0.0, now - b.last);
  b.last = now;
  b.packets = std::min(b.packets + dt * budget.packets_per_second,
                       budget.packets_per_second * budget.burst_seconds);
  b.bytes = std::min(b.bytes + dt * budget.bytes_per_second,
                     budget.bytes_per_second * budget.burst_seconds);
  b.packets -= 1.0;
  b.bytes -= static_cast<double>(bytes);
  return b.packets >= 0.0 && b.bytes >= 0.0;
}

// ---------------------------------------------------------------- packets

void RelayServer::on_packet(PeerId peer, Channel channel, std::span<const std::byte> bytes,
                            double now) {
  const std::size_t c = find_conn(peer);
  if (c == conns_.size()) {
    drop_log_.drop(now, link_.peer_name(peer), channel,
                   bytes.empty() ? kNoType : std::to_integer<int>(bytes[0]),
                   wire_error(DropReason::kUnknownPeer, "peer"));
    return;
  }
  Conn& conn = conns_[c];
  if (!within_budget(conn, bytes.size(), now)) {
    if (conn.state == ConnState::kMember) {
      ++stats_.floods_cut;
      return refuse(c, RelayRefusal::kFlooding, now);
    }
  }
  if (bytes.empty()) {
    drop_log_.drop(now, link_.peer_name(peer), channel, kNoType,
                   wire_error(DropReason::kEmpty, "packet"));
    return;
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  if (is_relay_type(type) && !relay_channel_allowed(type, channel)) {
    drop_log_.drop(now, link_.peer_name(peer), channel, type,
                   wire_error(DropReason::kWrongChannel, "channel"));
    return;
  }
  if (conn.state == ConnState::kPending) {
    return on_pending_packet(c, channel, bytes, now);
  }
  on_member_packet(c, channel, bytes, now);
}

void RelayServer::on_pending_packet(std::size_t c, Channel channel,
                                    std::span<const std::byte> bytes, double now) {
  Conn& conn = conns_[c];
  if (++conn.packets > config_.max_pending_packets) {
    ++stats_.pending_chatty;
    if (warn_budget_.take(now)) {
      log().warn("relay: letting go of {}: more packets than entering a room needs",
                 link_.peer_name(conn.peer));
    }
    return release(c, kStrangerCode, now, "chatty");
  }
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  if (type == static_cast<std::uint8_t>(RelayType::kKeepalive)) {
    if (const WireResult e = decode_keepalive(bytes); !e.ok()) {
      drop_log_.drop(now, link_.peer_name(conn.peer), channel, type, e);
    }
    return;
  }
  if (type != static_cast<std::uint8_t>(RelayType::kEnter)) {
    drop_log_.drop(
        now, link_.peer_name(conn.peer), channel, type,
        wire_error(is_relay_type(type) ? DropReason::kUnexpected : DropReason::kUnknownType,
                   "pending"));
    return;
  }
  RelayEnter m;
  if (const WireResult e = decode(bytes, m); !e.ok()) {
    drop_log_.drop(now, link_.peer_name(conn.peer), channel, type, e);
    if (e.reason == DropReason::kWrongVersion) {
      ++stats_.refused_version;
      refuse(c, RelayRefusal::kVersion, now);
    }
    return;
  }
  on_enter(c, m, now);
}

std::size_t RelayServer::find_room(const RoomToken& token) const {
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    if (rooms_[r].used && rooms_[r].token == token) {
      return r;
    }
  }
  return rooms_.size();
}

std::size_t RelayServer::find_or_make_room(const RoomToken& token,
                                           std::span<const std::uint8_t> params) {
  if (const std::size_t r = find_room(token); r < rooms_.size()) {
    return r;
  }
  for (std::size_t r = 0; r < rooms_.size(); ++r) {
    if (!rooms_[r].used) {
      Room& room = rooms_[r];
      room = Room{};
      room.used = true;
      room.token = token;
      room.params_size = static_cast<std::uint8_t>(params.size());
      std::copy(params.begin(), params.end(), room.params.begin());
      ++room_count_;
      ++stats_.rooms_created;
      return r;
    }
  }
  return rooms_.size();
}

MemberId RelayServer::next_member_id(Room& room) {
  // Ids go round 1 … 254, so that one who leaves and comes back gets a fresh id.
  for (int tries = 0; tries < kLastMember; ++tries) {
    const MemberId id = room.next_id;
    room.next_id = id == kLastMember ? kFirstMember : static_cast<MemberId>(id + 1);
    const auto taken = std::any_of(room.members.begin(), room.members.begin() + room.count,
                                   [&](const Member& m) { return m.id == id; });
    if (!taken) {
      return id;
    }
  }
  return kNoMember;  // cannot happen: a room holds at most kMaxRoomPeople
}

void RelayServer::on_enter(std::size_t c, const RelayEnter& m, double now) {
  const std::size_t r = find_or_make_room(m.room, m.params);
  if (r == rooms_.size()) {
    ++stats_.refused_relay_full;
    return refuse(c, RelayRefusal::kRelayFull, now);
  }
  Room& room = rooms_[r];
  if (room.count >= config_.max_people) {
    ++stats_.refused_room_full;
    return refuse(c, RelayRefusal::kRoomFull, now);
  }
  Conn& conn = conns_[c];
  const MemberId id = next_member_id(room);
  // Tell the newcomer who is there (and the room's params), then tell them.
  RelayEntered entered;
  entered.self = id;
  entered.params = {room.params.data(), room.params_size};
  entered.count = static_cast<std::uint8_t>(room.count);
  for (std::size_t i = 0; i < room.count; ++i) {
    entered.members[i] = RoomMember{room.members[i].id, room.members[i].announce_view()};
  }
  Member& member = room.members[room.count];
  member = Member{};
  member.id = id;
  member.conn = c;
  member.announce_size = static_cast<std::uint8_t>(m.announce.size());
  std::copy(m.announce.begin(), m.announce.end(), member.announce.begin());
  conn.state = ConnState::kMember;
  conn.room = r;
  conn.id = id;
  --pending_count_;
  ++stats_.entered;
  send(c, Channel::kReliable, std::span(tx_).first(encode(entered, tx_)));
  RelayJoined joined;
  joined.member = RoomMember{id, member.announce_view()};
  const std::size_t n = encode(joined, tx_);
  for (std::size_t i = 0; i < room.count; ++i) {
    send(room.members[i].conn, Channel::kReliable, std::span(tx_).first(n));
  }
  ++room.count;
  note(now, "entered", c, room.count);
}

void RelayServer::remove_member(std::size_t c, double now, const char* why) {
  Conn& conn = conns_[c];
  Room& room = rooms_[conn.room];
  const auto end = room.members.begin() + room.count;
  const auto it =
      std::find_if(room.members.begin(), end, [&](const Member& m) { return m.conn == c; });
  if (it != end) {
    std::move(it + 1, end, it);
    --room.count;
  }
  ++stats_.left;
  note(now, why, c, room.count);
  RelayLeft left;
  left.id = conn.id;
  const std::size_t n = encode(left, tx_);
  for (std::size_t i = 0; i < room.count; ++i) {
    send(room.members[i].conn, Channel::kReliable, std::span(tx_).first(n));
  }
  if (room.count == 0) {
    room = Room{};
    --room_count_;
    ++stats_.rooms_forgotten;
  }
  conn.state = ConnState::kPending;  // the caller frees the slot
  ++pending_count_;
}

void RelayServer::note(double now, const char* what, std::size_t c, std::size_t room_size) {
  if (!join_log_budget_.take(now)) {
    return;
  }
  const Conn& conn = conns_[c];
  const std::uint64_t held = join_log_budget_.held_back();
  log().info("relay: member {} of room {} {} ({} now, {}){}", conn.id,
             room_label(rooms_[conn.room].token), what, room_size, link_.peer_name(conn.peer),
             held > 0 ? " (" + std::to_string(held) + " lines held back)" : std::string());
}

void RelayServer::on_member_packet(std::size_t c, Channel channel, std::span<const std::byte> bytes,
                                   double now) {
  Conn& conn = conns_[c];
  const auto type = std::to_integer<std::uint8_t>(bytes[0]);
  if (type == static_cast<std::uint8_t>(RelayType::kForward)) {
    RelayForward m;
    if (const WireResult e = decode(bytes, m); !e.ok()) {
      drop_log_.drop(now, link_.peer_name(conn.peer), channel, type, e);
      return;
    }
    conn.last_heard = now;
    return forward(c, channel, m, now);
  }
  if (type == static_cast<std::uint8_t>(RelayType::kKeepalive)) {
    if (const WireResult e = decode_keepalive(bytes); !e.ok()) {
      drop_log_.drop(now, link_.peer_name(conn.peer), channel, type, e);
      return;
    }
    conn.last_heard = now;
    return;
  }
  drop_log_.drop(
      now, link_.peer_name(conn.peer), channel, type,
      wire_error(is_relay_type(type) ? DropReason::kUnexpected : DropReason::kUnknownType,
                 "member"));
}

void RelayServer::forward(std::size_t c, Channel channel, const RelayForward& m, double now) {
  const Conn& conn = conns_[c];
  const Room& room = rooms_[conn.room];
  ++stats_.forwards_in;
  stats_.bytes_in += m.payload.size();
  const std::size_t n = encode_forwarded(conn.id, m.payload, tx_);
  const std::span<const std::byte> out = std::span(tx_).first(n);
  bool delivered = false;
  // Members that could not take a reliable copy (their ENet queue is full): losing a reliable
  // message silently would leave their room state wrong, so they are let go and come back fresh.
  std::array<std::size_t, kMaxRoomPeople> behind{};
  std::size_t behind_count = 0;
  for (std::size_t i = 0; i < room.count; ++i) {
    const Member& to = room.members[i];
    if (to.conn == c || (m.to != kAllMembers && to.id != m.to)) {
      continue;
    }
    delivered = true;
    if (send(to.conn, channel, out)) {
      ++stats_.forwards_out;
      stats_.bytes_out += m.payload.size();
      conns_[to.conn].last_sent = now;
    } else if (channel == Channel::kReliable) {
      behind[behind_count++] = to.conn;
    }
  }
  if (!delivered && m.to != kAllMembers) {
    ++stats_.to_absent;
  }
  for (std::size_t i = 0; i < behind_count; ++i) {
    ++stats_.members_behind;
    if (warn_budget_.take(now)) {
      log().warn("relay: letting go of {}: it cannot keep up with its room's reliable messages",
                 link_.peer_name(conns_[behind[i]].peer));
    }
    release(behind[i], kLeavingCode, now, "could not keep up");
  }
}

// ---------------------------------------------------------------- timers

void RelayServer::timers(double now) {
  std::array<std::byte, kRelayKeepaliveBytes> keepalive{};
  const std::span<const std::byte> k = std::span(keepalive).first(encode_keepalive(keepalive));
  for (std::size_t c = 0; c < conns_.size(); ++c) {
    Conn& conn = conns_[c];
    if (conn.state == ConnState::kPending && now - conn.since > config_.pending_timeout) {
      ++stats_.pending_timed_out;
      release(c, kStrangerCode, now, "timed out");
    } else if (conn.state == ConnState::kMember) {
      if (now - conn.last_heard > config_.member_timeout) {
        ++stats_.members_timed_out;
        release(c, kLeavingCode, now, "fell silent");
      } else if (now - conn.last_sent >= config_.keepalive_interval) {
        conn.last_sent = now;
        ++stats_.keepalives_sent;
        send(c, Channel::kReliable, k);
      }
    }
  }
}

}  // namespace deixis::net
