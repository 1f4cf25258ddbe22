#pragma once
// A transport, as the session sees it: connect, send on a channel to a peer, and a stream of
// events (a peer connected, disconnected, a packet received), each naming its peer. EnetLink is
// the real one (UDP via ENet); SimulatedNetwork makes an in-process pair with loss, delay, jitter,
// reordering and duplicates for tests and demos. The session does not know which it has.
//
// A host's link holds several peers at once: the one it serves and strangers still in their
// handshake (docs/protocol.md §6), so that a stranger holding a connection never keeps the
// rightful joiner out. A joiner's link holds at most its one connection.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "net/protocol.h"

namespace deixis::net {

// A connection, as the link names it: never reused while the link lives (0 is no peer).
using PeerId = std::uint32_t;
inline constexpr PeerId kNoPeer = 0;

struct LinkEvent {
  enum class Kind : std::uint8_t { kNone, kConnected, kDisconnected, kReceived };
  Kind kind = Kind::kNone;
  PeerId peer = kNoPeer;
  Channel channel = Channel::kReliable;
  std::span<const std::byte> bytes;  // kReceived: valid until the next call to next_event()
  std::uint32_t data = 0;            // kDisconnected: the peer's disconnect code, if any

  static LinkEvent connected(PeerId peer) {
    return make(Kind::kConnected, peer, Channel::kReliable, {}, 0);
  }
  static LinkEvent disconnected(PeerId peer, std::uint32_t code) {
    return make(Kind::kDisconnected, peer, Channel::kReliable, {}, code);
  }
  static LinkEvent received(PeerId peer, Channel channel, std::span<const std::byte> packet) {
    return make(Kind::kReceived, peer, channel, packet, 0);
  }

 private:
  static LinkEvent make(Kind kind, PeerId peer, Channel channel, std::span<const std::byte> bytes,
                        std::uint32_t data) {
    LinkEvent e;
    e.kind = kind;
    e.peer = peer;
    e.channel = channel;
    e.bytes = bytes;
    e.data = data;
    return e;
  }
};

class Link {
 public:
  virtual ~Link() = default;

  // Joiner: start a connection attempt (kConnected or kDisconnected for it follows) and return
  // its PeerId; kNoPeer when an attempt cannot even start. A host accepts peers whenever they
  // connect and has nothing to do here (kNoPeer).
  virtual PeerId connect() = 0;
  // Close the connection to `peer`: packets already sent go first, then the peer is told.
  // No kDisconnected event follows for this connection.
  virtual void disconnect(PeerId peer, std::uint32_t code) = 0;
  // Queue a packet and put it on the wire (tracking must not wait for the next service call).
  // False when `peer` is not connected or the packet cannot be queued.
  virtual bool send(PeerId peer, Channel channel, std::span<const std::byte> packet) = 0;
  // The next event, waiting at most `wait_ms` for one (0: poll).
  virtual LinkEvent next_event(std::uint32_t wait_ms) = 0;

  // "127.0.0.1:40412", for log lines; "none" for an unknown peer.
  virtual std::string_view peer_name(PeerId peer) const = 0;
  // The peer's network address without the port (IPv4, network byte order), for per-address
  // budgets; 0 when unknown.
  virtual std::uint32_t peer_address(PeerId peer) const = 0;
  virtual std::uint32_t round_trip_ms(PeerId peer) const = 0;  // 0 when unknown
};

}  // namespace deixis::net
