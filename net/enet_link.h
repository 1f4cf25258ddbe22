#pragma once
// The real transport: ENet over UDP (docs/protocol.md §1). Two channels: reliable (ENet's reliable,
// ordered) and tracking (unreliable; sent unsequenced so that a packet overtaken by a newer one
// still reaches the jitter buffer, which orders by our own sequence numbers — docs/decisions.md).
// Every tracking send is flushed at once, and ENet's packet throttle (which drops unreliable
// packets when round trips grow) is kept open. ENet is told the protocol's limits: packets above
// kMaxPacketBytes and more than kMaxWaitingBytes queued per peer are refused by ENet itself.
//
// A host holds up to kMaxHostPeers connections at once (at most kMaxPeersPerAddress from one
// network address, which ENet itself enforces): the session decides whom it serves and whom it
// turns away (docs/protocol.md §6). A joiner makes one attempt per connect(), each from a fresh
// UDP port (so that a connection still closing can never be mistaken for the next one).
//
// ENet allocates a packet per send and per receive (its own malloc); nothing else here does
// after construction.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "net/link.h"

typedef struct _ENetHost ENetHost;
typedef struct _ENetPeer ENetPeer;
typedef struct _ENetPacket ENetPacket;

namespace deixis::net {

inline constexpr std::size_t kMaxWaitingBytes = 256 * 1024;
inline constexpr std::size_t kMaxHostPeers = 64;
inline constexpr std::size_t kMaxPeersPerAddress = 8;
// A relay (docs/relay.md) serves many rooms from one host: it asks for more peers.
inline constexpr std::size_t kMaxLinkPeers = 2047;

// How many peers a host holds, and how many from one network address (ENet enforces both).
struct HostLimits {
  std::size_t max_peers = kMaxHostPeers;  // at most kMaxLinkPeers
  std::size_t max_peers_per_address = kMaxPeersPerAddress;
};

class EnetLink : public Link {
 public:
  // Listens on `port` of `bind_address` ("0.0.0.0", "127.0.0.1"); port 0 picks a free one (see
  // port()). Throws deixis::Error when the address is invalid or the port cannot be bound.
  static std::unique_ptr<EnetLink> host(const std::string& bind_address, std::uint16_t port,
                                        const HostLimits& limits = {});
  // Connects to `address`:`port` on each connect(), from `local_address` (default: any; tests
  // use another loopback address to play a stranger on another machine). Throws deixis::Error
  // for an unresolvable address.
  static std::unique_ptr<EnetLink> join(const std::string& address, std::uint16_t port,
                                        const std::string& local_address = "");

  ~EnetLink() override;
  EnetLink(const EnetLink&) = delete;
  EnetLink& operator=(const EnetLink&) = delete;

  PeerId connect() override;
  void disconnect(PeerId peer, std::uint32_t code) override;
  bool send(PeerId peer, Channel channel, std::span<const std::byte> packet) override;
  LinkEvent next_event(std::uint32_t wait_ms) override;
  std::string_view peer_name(PeerId peer) const override;
  std::uint32_t peer_address(PeerId peer) const override;
  std::uint32_t round_trip_ms(PeerId peer) const override;
  std::size_t connected_peers() const;  // peers connected now (served or in their handshake)

  std::uint16_t port() const;  // the local port (the one chosen, when 0 was asked for)
  // Services ENet until every closing connection has finished (the peer acknowledged our bye and
  // disconnect) or `max_ms` passed, so a process can exit without leaving its peer to time out.
  // True when everything finished.
  bool drain(std::uint32_t max_ms);
  // ENet's own time-out for the peer (ms); the session sets it above its heartbeat time-out so
  // that the session's visible time-out fires first.
  void set_timeout_ms(std::uint32_t ms) { timeout_ms_ = ms; }
  std::uint64_t ignored_packets() const { return ignored_packets_; }  // from peers let go

  // What went over the socket: UDP payloads (ENet's headers included, UDP/IP's not); for a
  // joiner, since its last connection attempt (each has its own socket).
  struct Traffic {
    std::uint64_t sent_bytes = 0;
    std::uint64_t sent_datagrams = 0;
    std::uint64_t received_bytes = 0;
    std::uint64_t received_datagrams = 0;
  };
  Traffic traffic() const;

 private:
  // One ENet peer slot, as this link knows it.
  struct Slot {
    PeerId id = kNoPeer;  // kNoPeer: free, or let go (its events are ignored)
    std::uint32_t connect_id = 0;
    bool connected = false;
    std::uint32_t address = 0;
    char name[64] = "none";  // "address:port": 45 + 1 + 5 bytes at most
  };

  EnetLink(ENetHost* host, bool is_host, std::uint32_t remote_ip, std::uint16_t remote_port,
           std::uint32_t local_ip);
  ENetHost* make_client_host() const;
  void reset_slots();
  Slot* slot_of(const ENetPeer* peer);
  const Slot* slot_of(PeerId id) const;
  ENetPeer* peer_of(PeerId id) const;
  PeerId adopt(ENetPeer* peer);
  LinkEvent on_connected(ENetPeer* peer, Slot& slot);
  void release_packet();

  ENetHost* host_ = nullptr;
  bool is_host_ = false;
  std::uint32_t remote_ip_ = 0;  // joiner: where to connect (network byte order, as ENet keeps it)
  std::uint16_t remote_port_ = 0;
  std::uint32_t local_ip_ = 0;    // joiner: where to connect from (0: any)
  std::vector<Slot> slots_;       // one per ENet peer of host_
  std::uint32_t generation_ = 0;  // makes PeerIds unique: +1 per connection
  ENetPacket* held_ = nullptr;    // the packet the last kReceived event points into
  std::uint32_t timeout_ms_ = 5000;
  std::uint64_t ignored_packets_ = 0;
};

}  // namespace deixis::net
