#include "net/enet_link.h"

#include <enet/enet.h>

#include <algorithm>
#include <cstdio>

#include "gesture/error.h"

namespace deixis::net {

namespace {

// ENet's global initialisation does nothing on POSIX systems beyond returning 0, but the API
// requires it before use; done once per process.
void initialise_enet() {
  static const bool ready = enet_initialize() == 0;
  if (!ready) {
    throw Error("ENet: enet_initialize failed");
  }
}

ENetAddress resolve(const std::string& address, std::uint16_t port) {
  ENetAddress a{};
  a.port = port;
  if (address.empty() || address == "0.0.0.0" || address == "*") {
    a.host = ENET_HOST_ANY;
  } else if (enet_address_set_host(&a, address.c_str()) != 0) {
    throw Error("net: cannot resolve address '" + address + "'");
  }
  return a;
}

void apply_limits(ENetHost* host) {
  host->maximumPacketSize = kMaxPacketBytes;
  host->maximumWaitingData = kMaxWaitingBytes;
}

// A joiner's ENet host: one peer, a fresh ephemeral port.
ENetHost* client_host() {
  ENetHost* host = enet_host_create(nullptr, 1, kChannelCount, 0, 0);
  if (host == nullptr) {
    throw Error("net: cannot create an ENet client host");
  }
  apply_limits(host);
  return host;
}

// Tells every live peer of `host` at once (the notice is sent without waiting for an
// acknowledgement) and destroys it.
void close_host(ENetHost* host) {
  for (std::size_t i = 0; i < host->peerCount; ++i) {
    ENetPeer* p = &host->peers[i];
    if (p->state != ENET_PEER_STATE_DISCONNECTED) {
      enet_peer_disconnect_now(p, static_cast<std::uint32_t>(ByeReason::kLeaving));
    }
  }
  enet_host_destroy(host);
}

}  // namespace

std::unique_ptr<EnetLink> EnetLink::host(const std::string& bind_address, std::uint16_t port) {
  initialise_enet();
  const ENetAddress address = resolve(bind_address, port);
  // Room for one peer in session, plus a few that are being turned away.
  ENetHost* host = enet_host_create(&address, 4, kChannelCount, 0, 0);
  if (host == nullptr) {
    throw Error("net: cannot listen on " + bind_address + ":" + std::to_string(port) +
                " (port in use?)");
  }
  apply_limits(host);
  return std::unique_ptr<EnetLink>(new EnetLink(host, true, 0, 0));
}

std::unique_ptr<EnetLink> EnetLink::join(const std::string& address, std::uint16_t port) {
  initialise_enet();
  const ENetAddress remote = resolve(address, port);
  if (remote.host == ENET_HOST_ANY || port == 0) {
    throw Error("net: cannot join '" + address + ":" + std::to_string(port) + "'");
  }
  return std::unique_ptr<EnetLink>(new EnetLink(client_host(), false, remote.host, port));
}

EnetLink::EnetLink(ENetHost* host, bool is_host, std::uint32_t remote_ip, std::uint16_t remote_port)
    : host_(host), is_host_(is_host), remote_ip_(remote_ip), remote_port_(remote_port) {}

EnetLink::~EnetLink() {
  release_packet();
  if (host_ != nullptr) {
    close_host(host_);
  }
}

bool EnetLink::drain(std::uint32_t max_ms) {
  release_packet();
  const std::uint32_t start = enet_time_get();
  const auto busy = [this] {
    for (std::size_t i = 0; i < host_->peerCount; ++i) {
      const ENetPeerState state = host_->peers[i].state;
      if (state != ENET_PEER_STATE_DISCONNECTED && &host_->peers[i] != peer_) {
        return true;
      }
    }
    return false;
  };
  ENetEvent event{};
  while (busy() && enet_time_get() - start < max_ms) {
    if (enet_host_service(host_, &event, 5) > 0 && event.type == ENET_EVENT_TYPE_RECEIVE) {
      enet_packet_destroy(event.packet);
    }
  }
  return !busy();
}

EnetLink::Traffic EnetLink::traffic() const {
  return {host_->totalSentData, host_->totalSentPackets, host_->totalReceivedData,
          host_->totalReceivedPackets};
}

std::uint16_t EnetLink::port() const {
  return host_->address.port;
}

std::uint32_t EnetLink::round_trip_ms() const {
  return peer_ != nullptr && peer_connected_ ? peer_->roundTripTime : 0;
}

void EnetLink::adopt(ENetPeer* peer) {
  peer_ = peer;
  peer_connect_id_ = peer->connectID;
  enet_peer_timeout(peer, 0, timeout_ms_, timeout_ms_);
  char ip[46] = "?";
  enet_address_get_host_ip(&peer->address, ip, sizeof ip);
  const int n = std::snprintf(peer_name_storage_, sizeof peer_name_storage_, "%s:%u", ip,
                              static_cast<unsigned>(peer->address.port));
  peer_name_ = std::string_view(
      peer_name_storage_,
      static_cast<std::size_t>(std::clamp(n, 0, static_cast<int>(sizeof peer_name_storage_) - 1)));
}

bool EnetLink::connect() {
  if (is_host_ || peer_ != nullptr) {
    return is_host_;
  }
  // Every attempt from a new socket: a closing connection's late packets (a disconnect still
  // being resent) come from the old port and cannot be taken for the new connection's, even by
  // a host restarted on the same port.
  release_packet();
  ENetHost* fresh = enet_host_create(nullptr, 1, kChannelCount, 0, 0);
  if (fresh == nullptr) {
    return false;
  }
  apply_limits(fresh);
  close_host(host_);
  host_ = fresh;
  ENetAddress remote{};
  remote.host = remote_ip_;
  remote.port = remote_port_;
  ENetPeer* peer = enet_host_connect(host_, &remote, kChannelCount, 0);
  if (peer == nullptr) {
    return false;
  }
  adopt(peer);
  peer_connected_ = false;
  enet_host_flush(host_);
  return true;
}

void EnetLink::disconnect(std::uint32_t code) {
  if (peer_ == nullptr) {
    return;
  }
  if (peer_connected_) {
    // Queued packets (a bye) go first; ENet then closes the connection by itself.
    enet_peer_disconnect_later(peer_, code);
    enet_host_flush(host_);
  } else {
    enet_peer_reset(peer_);  // an attempt in flight: abandon it
  }
  peer_ = nullptr;
  peer_connected_ = false;
}

bool EnetLink::send(Channel channel, std::span<const std::byte> packet) {
  if (peer_ == nullptr || !peer_connected_) {
    return false;
  }
  const std::uint32_t flags =
      channel == Channel::kReliable ? ENET_PACKET_FLAG_RELIABLE : ENET_PACKET_FLAG_UNSEQUENCED;
  ENetPacket* p = enet_packet_create(packet.data(), packet.size(), flags);
  if (p == nullptr) {
    return false;
  }
  if (enet_peer_send(peer_, static_cast<enet_uint8>(channel), p) != 0) {
    enet_packet_destroy(p);  // not consumed on failure (too large, or the peer is closing)
    return false;
  }
  enet_host_flush(host_);
  return true;
}

LinkEvent EnetLink::on_connected() {
  peer_connected_ = true;
  // ENet drops unreliable packets when round trips grow (its packet throttle). Tracking is a few
  // kB/s whatever happens, and a round trip that grows because a process was busy says nothing
  // about congestion; a dropped frame would only become missed tracking. So the throttle never
  // decelerates (both ends: ENet sends the setting to the peer too).
  enet_peer_throttle_configure(peer_, ENET_PEER_PACKET_THROTTLE_INTERVAL,
                               ENET_PEER_PACKET_THROTTLE_ACCELERATION, 0);
  return LinkEvent::connected();
}

void EnetLink::release_packet() {
  if (held_ != nullptr) {
    enet_packet_destroy(held_);
    held_ = nullptr;
  }
}

LinkEvent EnetLink::next_event(std::uint32_t wait_ms) {
  release_packet();
  ENetEvent event{};
  while (enet_host_service(host_, &event, wait_ms) > 0) {
    wait_ms = 0;
    const bool current =
        event.peer != nullptr && event.peer == peer_ &&
        (event.peer->connectID == peer_connect_id_ || event.type == ENET_EVENT_TYPE_DISCONNECT);
    switch (event.type) {
      case ENET_EVENT_TYPE_CONNECT:
        if (is_host_ && peer_ == nullptr) {
          adopt(event.peer);
          return on_connected();
        }
        if (!is_host_ && current) {
          peer_connect_id_ = event.peer->connectID;
          return on_connected();
        }
        if (is_host_) {
          enet_peer_disconnect(event.peer, static_cast<std::uint32_t>(ByeReason::kBusy));
        }
        break;
      case ENET_EVENT_TYPE_DISCONNECT:
        if (current) {
          peer_ = nullptr;
          peer_connected_ = false;
          return LinkEvent::disconnected(event.data);
        }
        break;
      case ENET_EVENT_TYPE_RECEIVE:
        if (current && peer_connected_ && event.channelID < kChannelCount) {
          held_ = event.packet;
          return LinkEvent::received(
              static_cast<Channel>(event.channelID),
              std::span<const std::byte>(reinterpret_cast<const std::byte*>(held_->data),
                                         held_->dataLength));
        }
        ++ignored_packets_;
        enet_packet_destroy(event.packet);
        break;
      case ENET_EVENT_TYPE_NONE:
        break;
    }
  }
  return {};
}

}  // namespace deixis::net
