#pragma once
// The real transport: ENet over UDP (DESIGN §9). Two channels: reliable (ENet's reliable,
// ordered) and tracking (unreliable; sent unsequenced so that a packet overtaken by a newer one
// still reaches the jitter buffer, which orders by our own sequence numbers — docs/decisions.md).
// Every tracking send is flushed at once, and ENet's packet throttle (which drops unreliable
// packets when round trips grow) is kept open. ENet is told the protocol's limits: packets above
// kMaxPacketBytes and more than kMaxWaitingBytes queued per peer are refused by ENet itself.
//
// A host serves one peer at a time; a second one is disconnected with ByeReason::kBusy as ENet's
// disconnect data. A joiner makes one attempt per connect(), each from a fresh UDP port (so
// that a connection still closing can never be mistaken for the next one).
//
// ENet allocates a packet per send and per receive (its own malloc); nothing else here does
// after construction.

#include <cstdint>
#include <memory>
#include <string>

#include "net/link.h"

typedef struct _ENetHost ENetHost;
typedef struct _ENetPeer ENetPeer;
typedef struct _ENetPacket ENetPacket;

namespace deixis::net {

inline constexpr std::size_t kMaxWaitingBytes = 256 * 1024;

class EnetLink : public Link {
 public:
  // Listens on `port` of `bind_address` ("0.0.0.0", "127.0.0.1"); port 0 picks a free one (see
  // port()). Throws deixis::Error when the address is invalid or the port cannot be bound.
  static std::unique_ptr<EnetLink> host(const std::string& bind_address, std::uint16_t port);
  // Connects to `address`:`port` on each connect(). Throws deixis::Error for an unresolvable
  // address.
  static std::unique_ptr<EnetLink> join(const std::string& address, std::uint16_t port);

  ~EnetLink() override;
  EnetLink(const EnetLink&) = delete;
  EnetLink& operator=(const EnetLink&) = delete;

  bool connect() override;
  void disconnect(std::uint32_t code) override;
  bool send(Channel channel, std::span<const std::byte> packet) override;
  LinkEvent next_event(std::uint32_t wait_ms) override;
  std::string_view peer_name() const override { return peer_name_; }
  std::uint32_t round_trip_ms() const override;

  std::uint16_t port() const;  // the local port (the one chosen, when 0 was asked for)
  // Services ENet until every closing connection has finished (the peer acknowledged our bye and
  // disconnect) or `max_ms` passed, so a process can exit without leaving its peer to time out.
  // True when everything finished.
  bool drain(std::uint32_t max_ms);
  // ENet's own time-out for the peer (ms); the session sets it above its heartbeat time-out so
  // that the session's visible time-out fires first.
  void set_timeout_ms(std::uint32_t ms) { timeout_ms_ = ms; }
  std::uint64_t ignored_packets() const { return ignored_packets_; }  // from non-current peers

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
  EnetLink(ENetHost* host, bool is_host, std::uint32_t remote_ip, std::uint16_t remote_port);
  void adopt(ENetPeer* peer);
  LinkEvent on_connected();
  void release_packet();

  ENetHost* host_ = nullptr;
  bool is_host_ = false;
  std::uint32_t remote_ip_ = 0;  // joiner: where to connect (network byte order, as ENet keeps it)
  std::uint16_t remote_port_ = 0;
  ENetPeer* peer_ = nullptr;  // the current peer (connecting or connected)
  std::uint32_t peer_connect_id_ = 0;
  bool peer_connected_ = false;
  ENetPacket* held_ = nullptr;  // the packet the last kReceived event points into
  std::uint32_t timeout_ms_ = 5000;
  std::uint64_t ignored_packets_ = 0;
  char peer_name_storage_[64] = "none";
  std::string_view peer_name_ = peer_name_storage_;
};

}  // namespace deixis::net
