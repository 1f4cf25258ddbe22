#pragma once
// A transport to one peer, as the session sees it: connect, send on a channel, and a stream of
// events (connected, disconnected, packet received). EnetLink is the real one (UDP via ENet);
// SimulatedNetwork makes an in-process pair with loss, delay, jitter, reordering and duplicates
// for tests and demos. The session does not know which it has.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "net/protocol.h"

namespace deixis::net {

struct LinkEvent {
  enum class Kind : std::uint8_t { kNone, kConnected, kDisconnected, kReceived };
  Kind kind = Kind::kNone;
  Channel channel = Channel::kReliable;
  std::span<const std::byte> bytes;  // kReceived: valid until the next call to next_event()
  std::uint32_t data = 0;            // kDisconnected: the peer's disconnect code, if any

  static LinkEvent connected() { return make(Kind::kConnected, Channel::kReliable, {}, 0); }
  static LinkEvent disconnected(std::uint32_t code) {
    return make(Kind::kDisconnected, Channel::kReliable, {}, code);
  }
  static LinkEvent received(Channel channel, std::span<const std::byte> packet) {
    return make(Kind::kReceived, channel, packet, 0);
  }

 private:
  static LinkEvent make(Kind kind, Channel channel, std::span<const std::byte> bytes,
                        std::uint32_t data) {
    LinkEvent e;
    e.kind = kind;
    e.channel = channel;
    e.bytes = bytes;
    e.data = data;
    return e;
  }
};

class Link {
 public:
  virtual ~Link() = default;

  // Joiner: start a connection attempt (kConnected or kDisconnected follows). Host: nothing to do,
  // it accepts a peer whenever one connects. False when an attempt cannot even start.
  virtual bool connect() = 0;
  // Close the connection to the peer: packets already sent go first, then the peer is told.
  // No kDisconnected event follows for this connection.
  virtual void disconnect(std::uint32_t code) = 0;
  // Queue a packet and put it on the wire (tracking must not wait for the next service call).
  // False when there is no connected peer or the packet cannot be queued.
  virtual bool send(Channel channel, std::span<const std::byte> packet) = 0;
  // The next event, waiting at most `wait_ms` for one (0: poll).
  virtual LinkEvent next_event(std::uint32_t wait_ms) = 0;

  virtual std::string_view peer_name() const = 0;   // "127.0.0.1:40412", for log lines
  virtual std::uint32_t round_trip_ms() const = 0;  // 0 when unknown
};

}  // namespace deixis::net
