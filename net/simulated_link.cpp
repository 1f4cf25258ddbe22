#include "net/simulated_link.h"

#include <algorithm>
#include <cmath>

namespace deixis::net {

namespace {
// What a reliable packet loses per loss: ENet resends after about a round trip plus margin.
constexpr double kResendMargin = 0.1;
constexpr double kConnectTimeout = 1.0;  // s, an attempt into a partition fails after this
}  // namespace

SimulatedNetwork::SimulatedNetwork(const LinkConditions& conditions, std::uint64_t seed)
    : conditions_(conditions),
      rng_(seed),
      links_{End(*this, Side::kHost), End(*this, Side::kJoiner)},
      in_flight_(kSlots) {
  for (InFlight& f : in_flight_) {
    f.bytes.reserve(kSlotBytes);
  }
  for (EndState& e : ends_) {
    e.current.reserve(kMaxPacketBytes);
  }
}

std::uint32_t SimulatedNetwork::End::round_trip_ms(PeerId) const {
  return static_cast<std::uint32_t>(std::lround(2000.0 * net_->conditions_.delay));
}

double SimulatedNetwork::one_way_delay() {
  double d = conditions_.delay + conditions_.jitter * gaussian_(rng_);
  if (chance(conditions_.reorder)) {
    ++stats_.reordered;
    d += conditions_.reorder_delay;
  }
  return std::max(0.0, d);
}

bool SimulatedNetwork::chance(double p) {
  return p > 0.0 && uniform_(rng_) < p;
}

void SimulatedNetwork::enqueue(Side to, LinkEvent::Kind kind, Channel channel, double at,
                               std::uint32_t data, std::uint64_t connection,
                               std::span<const std::byte> bytes) {
  const auto free = std::find_if(in_flight_.begin(), in_flight_.end(),
                                 [](const InFlight& f) { return !f.active; });
  if (free == in_flight_.end()) {
    ++stats_.overflow;
    return;
  }
  free->active = true;
  free->deliver_at = at;
  free->order = order_++;
  free->to = to;
  free->kind = kind;
  free->channel = channel;
  free->data = data;
  free->connection = connection;
  free->bytes.assign(bytes.begin(), bytes.end());
}

PeerId SimulatedNetwork::connect(Side side) {
  if (side != Side::kJoiner || connecting_ || state(side).connected) {
    return kNoPeer;
  }
  connecting_ = true;
  const std::uint64_t attempt = ++connection_;
  if (partitioned_) {
    enqueue(Side::kJoiner, LinkEvent::Kind::kDisconnected, Channel::kReliable,
            now_ + kConnectTimeout, 0, attempt, {});
  } else {
    enqueue(Side::kHost, LinkEvent::Kind::kConnected, Channel::kReliable, now_ + conditions_.delay,
            0, attempt, {});
  }
  return static_cast<PeerId>(attempt);
}

void SimulatedNetwork::disconnect(Side side, PeerId peer, std::uint32_t code) {
  EndState& end = state(side);
  if (side == Side::kJoiner && connecting_ && peer == static_cast<PeerId>(connection_)) {
    connecting_ = false;  // an attempt in flight is abandoned
  }
  if (!end.connected || peer != static_cast<PeerId>(end.connection)) {
    return;
  }
  end.connected = false;
  // Whatever was sent before goes first (reliable order), then the peer learns of it.
  EndState& far_end = state(other(side));
  if (!partitioned_) {
    const double at = std::max(now_ + conditions_.delay, far_end.last_reliable_at);
    far_end.last_reliable_at = at;
    enqueue(other(side), LinkEvent::Kind::kDisconnected, Channel::kReliable, at, code,
            end.connection, {});
  }
}

bool SimulatedNetwork::send(Side from, PeerId peer, Channel channel,
                            std::span<const std::byte> packet) {
  const EndState& sender = state(from);
  if (!sender.connected || peer != static_cast<PeerId>(sender.connection)) {
    return false;
  }
  ++stats_.sent;
  if (partitioned_) {
    ++stats_.lost;
    return true;
  }
  const Side to = other(from);
  if (channel == Channel::kReliable) {
    double at = now_ + one_way_delay();
    while (chance(conditions_.loss)) {
      at += 2.0 * conditions_.delay + kResendMargin;
    }
    EndState& receiver = state(to);
    at = std::max(at, receiver.last_reliable_at);
    receiver.last_reliable_at = at;
    enqueue(to, LinkEvent::Kind::kReceived, channel, at, 0, sender.connection, packet);
    return true;
  }
  if (chance(conditions_.loss)) {
    ++stats_.lost;
    return true;
  }
  enqueue(to, LinkEvent::Kind::kReceived, channel, now_ + one_way_delay(), 0, sender.connection,
          packet);
  if (chance(conditions_.duplicate)) {
    ++stats_.duplicated;
    enqueue(to, LinkEvent::Kind::kReceived, channel, now_ + one_way_delay(), 0, sender.connection,
            packet);
  }
  return true;
}

void SimulatedNetwork::inject(Side to, Channel channel, std::span<const std::byte> packet) {
  enqueue(to, LinkEvent::Kind::kReceived, channel, now_ + conditions_.delay, 0,
          state(to).connection, packet);
}

void SimulatedNetwork::inject_disconnect(Side to, std::uint32_t code) {
  enqueue(to, LinkEvent::Kind::kDisconnected, Channel::kReliable, now_ + conditions_.delay, code,
          state(to).connection, {});
}

LinkEvent SimulatedNetwork::deliver(Side side, InFlight& f) {
  EndState& end = state(side);
  const auto id = static_cast<PeerId>(f.connection);
  const bool current = end.connected && end.connection == f.connection;
  switch (f.kind) {
    case LinkEvent::Kind::kConnected:
      if (side == Side::kHost) {
        if (end.connected) {
          // Like EnetLink: a host with a peer turns a second one away.
          enqueue(Side::kJoiner, LinkEvent::Kind::kDisconnected, Channel::kReliable,
                  now_ + conditions_.delay, static_cast<std::uint32_t>(ByeReason::kBusy),
                  f.connection, {});
          return {};
        }
        end.connected = true;
        end.connection = f.connection;
        end.last_reliable_at = now_;
        enqueue(Side::kJoiner, LinkEvent::Kind::kConnected, Channel::kReliable,
                now_ + conditions_.delay, 0, f.connection, {});
        return LinkEvent::connected(id);
      }
      if (!connecting_ || f.connection != connection_) {
        return {};  // an abandoned attempt
      }
      connecting_ = false;
      end.connected = true;
      end.connection = f.connection;
      end.last_reliable_at = now_;
      return LinkEvent::connected(id);
    case LinkEvent::Kind::kDisconnected:
      if (side == Side::kJoiner && connecting_ && f.connection == connection_) {
        connecting_ = false;
        return LinkEvent::disconnected(id, f.data);
      }
      if (!current) {
        return {};
      }
      end.connected = false;
      return LinkEvent::disconnected(id, f.data);
    case LinkEvent::Kind::kReceived:
      if (!current) {
        return {};
      }
      ++stats_.delivered;
      end.current.assign(f.bytes.begin(), f.bytes.end());
      return LinkEvent::received(id, f.channel, end.current);
    case LinkEvent::Kind::kNone:
      break;
  }
  return {};
}

LinkEvent SimulatedNetwork::next_event(Side side) {
  while (true) {
    InFlight* next = nullptr;
    for (InFlight& f : in_flight_) {
      if (f.active && f.to == side && f.deliver_at <= now_ &&
          (next == nullptr || f.deliver_at < next->deliver_at ||
           (f.deliver_at == next->deliver_at && f.order < next->order))) {
        next = &f;
      }
    }
    if (next == nullptr) {
      return {};
    }
    next->active = false;
    const LinkEvent event = deliver(side, *next);
    if (event.kind != LinkEvent::Kind::kNone) {
      return event;
    }
  }
}

}  // namespace deixis::net
