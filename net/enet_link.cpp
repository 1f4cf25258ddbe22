#include "net/enet_link.h"

#include <enet/enet.h>

#include <algorithm>
#include <cstdio>

#include "core/error.h"

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
  host->duplicatePeers = kMaxPeersPerAddress;  // ENet ignores more connections from one address
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

// PeerId: the slot's index + 1 in the low 11 bits, the connection's generation above.
constexpr std::uint32_t kIndexBits = 11;
static_assert(kMaxLinkPeers < (1u << kIndexBits));

PeerId make_id(std::size_t index, std::uint32_t generation) {
  const std::uint32_t g = generation & ((1u << (32 - kIndexBits)) - 1u);
  return (g << kIndexBits) | static_cast<std::uint32_t>(index + 1);
}

std::size_t index_of(PeerId id) {
  return static_cast<std::size_t>(id & ((1u << kIndexBits) - 1u)) - 1;
}

}  // namespace

std::unique_ptr<EnetLink> EnetLink::host(const std::string& bind_address, std::uint16_t port,
                                         const HostLimits& limits) {
  initialise_enet();
  const ENetAddress address = resolve(bind_address, port);
  if (limits.max_peers == 0 || limits.max_peers > kMaxLinkPeers ||
      limits.max_peers_per_address == 0) {
    throw Error("net: a host holds 1 to " + std::to_string(kMaxLinkPeers) + " peers");
  }
  // Room for the peer in session and for strangers in their handshake (docs/protocol.md §6).
  ENetHost* host = enet_host_create(&address, limits.max_peers, kChannelCount, 0, 0);
  if (host == nullptr) {
    throw Error("net: cannot listen on " + bind_address + ":" + std::to_string(port) +
                " (port in use?)");
  }
  apply_limits(host);
  host->duplicatePeers = limits.max_peers_per_address;
  return std::unique_ptr<EnetLink>(new EnetLink(host, true, 0, 0, 0));
}

std::unique_ptr<EnetLink> EnetLink::join(const std::string& address, std::uint16_t port,
                                         const std::string& local_address) {
  initialise_enet();
  const ENetAddress remote = resolve(address, port);
  if (remote.host == ENET_HOST_ANY || port == 0) {
    throw Error("net: cannot join '" + address + ":" + std::to_string(port) + "'");
  }
  const std::uint32_t local = local_address.empty() ? 0 : resolve(local_address, 0).host;
  auto link = std::unique_ptr<EnetLink>(new EnetLink(nullptr, false, remote.host, port, local));
  link->host_ = link->make_client_host();
  if (link->host_ == nullptr) {
    throw Error("net: cannot create an ENet client host" +
                (local_address.empty() ? std::string() : " on " + local_address));
  }
  link->reset_slots();
  return link;
}

EnetLink::EnetLink(ENetHost* host, bool is_host, std::uint32_t remote_ip, std::uint16_t remote_port,
                   std::uint32_t local_ip)
    : host_(host),
      is_host_(is_host),
      remote_ip_(remote_ip),
      remote_port_(remote_port),
      local_ip_(local_ip) {
  if (host_ != nullptr) {
    reset_slots();
  }
}

// A joiner's ENet host: one peer, a fresh ephemeral port.
ENetHost* EnetLink::make_client_host() const {
  ENetAddress local{};
  local.host = local_ip_;
  local.port = 0;
  ENetHost* host = enet_host_create(local_ip_ == 0 ? nullptr : &local, 1, kChannelCount, 0, 0);
  if (host != nullptr) {
    apply_limits(host);
  }
  return host;
}

void EnetLink::reset_slots() {
  slots_.assign(host_->peerCount, Slot{});
}

EnetLink::Slot* EnetLink::slot_of(const ENetPeer* peer) {
  if (peer == nullptr || peer < host_->peers || peer >= host_->peers + host_->peerCount) {
    return nullptr;
  }
  return &slots_[static_cast<std::size_t>(peer - host_->peers)];
}

const EnetLink::Slot* EnetLink::slot_of(PeerId id) const {
  if (id == kNoPeer) {
    return nullptr;
  }
  const std::size_t index = index_of(id);
  return index < slots_.size() && slots_[index].id == id ? &slots_[index] : nullptr;
}

ENetPeer* EnetLink::peer_of(PeerId id) const {
  return slot_of(id) != nullptr ? &host_->peers[index_of(id)] : nullptr;
}

EnetLink::~EnetLink() {
  release_packet();
  if (host_ != nullptr) {
    close_host(host_);
  }
}

bool EnetLink::drain(std::uint32_t max_ms) {
  release_packet();
  const std::uint32_t start = enet_time_get();
  // Closing: a peer ENet still has that this link let go.
  const auto busy = [this] {
    for (std::size_t i = 0; i < host_->peerCount; ++i) {
      if (host_->peers[i].state != ENET_PEER_STATE_DISCONNECTED && slots_[i].id == kNoPeer) {
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

std::uint32_t EnetLink::round_trip_ms(PeerId id) const {
  const Slot* slot = slot_of(id);
  return slot != nullptr && slot->connected ? peer_of(id)->roundTripTime : 0;
}

std::string_view EnetLink::peer_name(PeerId id) const {
  const Slot* slot = slot_of(id);
  return slot != nullptr ? std::string_view(slot->name) : std::string_view("none");
}

std::uint32_t EnetLink::peer_address(PeerId id) const {
  const Slot* slot = slot_of(id);
  return slot != nullptr ? slot->address : 0;
}

std::size_t EnetLink::connected_peers() const {
  return static_cast<std::size_t>(
      std::count_if(slots_.begin(), slots_.end(), [](const Slot& s) { return s.connected; }));
}

PeerId EnetLink::adopt(ENetPeer* peer) {
  const auto index = static_cast<std::size_t>(peer - host_->peers);
  Slot& slot = slots_[index];
  slot = Slot{};
  slot.id = make_id(index, ++generation_);
  slot.connect_id = peer->connectID;
  slot.address = peer->address.host;
  enet_peer_timeout(peer, 0, timeout_ms_, timeout_ms_);
  char ip[46] = "?";
  enet_address_get_host_ip(&peer->address, ip, sizeof ip);
  std::snprintf(slot.name, sizeof slot.name, "%s:%u", ip,
                static_cast<unsigned>(peer->address.port));
  return slot.id;
}

PeerId EnetLink::connect() {
  if (is_host_) {
    return kNoPeer;
  }
  if (std::any_of(slots_.begin(), slots_.end(), [](const Slot& s) { return s.id != kNoPeer; })) {
    return kNoPeer;  // an attempt or a connection is still ours
  }
  // Every attempt from a new socket: a closing connection's late packets (a disconnect still
  // being resent) come from the old port and cannot be taken for the new connection's, even by
  // a host restarted on the same port.
  release_packet();
  ENetHost* fresh = make_client_host();
  if (fresh == nullptr) {
    return kNoPeer;
  }
  close_host(host_);
  host_ = fresh;
  reset_slots();
  ENetAddress remote{};
  remote.host = remote_ip_;
  remote.port = remote_port_;
  ENetPeer* peer = enet_host_connect(host_, &remote, kChannelCount, 0);
  if (peer == nullptr) {
    return kNoPeer;
  }
  const PeerId id = adopt(peer);
  enet_host_flush(host_);
  return id;
}

void EnetLink::disconnect(PeerId id, std::uint32_t code) {
  ENetPeer* peer = peer_of(id);
  if (peer == nullptr) {
    return;
  }
  Slot& slot = slots_[index_of(id)];
  if (slot.connected) {
    // Queued packets (a bye) go first; ENet then closes the connection by itself.
    enet_peer_disconnect_later(peer, code);
    enet_host_flush(host_);
  } else {
    enet_peer_reset(peer);  // an attempt in flight: abandon it
  }
  slot = Slot{};  // its later events are ignored
}

bool EnetLink::send(PeerId id, Channel channel, std::span<const std::byte> packet) {
  const Slot* slot = slot_of(id);
  if (slot == nullptr || !slot->connected) {
    return false;
  }
  ENetPeer* peer = peer_of(id);
  const std::uint32_t flags =
      channel == Channel::kReliable ? ENET_PACKET_FLAG_RELIABLE : ENET_PACKET_FLAG_UNSEQUENCED;
  ENetPacket* p = enet_packet_create(packet.data(), packet.size(), flags);
  if (p == nullptr) {
    return false;
  }
  if (enet_peer_send(peer, static_cast<enet_uint8>(channel), p) != 0) {
    enet_packet_destroy(p);  // not consumed on failure (too large, or the peer is closing)
    return false;
  }
  enet_host_flush(host_);
  return true;
}

LinkEvent EnetLink::on_connected(ENetPeer* peer, Slot& slot) {
  slot.connected = true;
  // ENet drops unreliable packets when round trips grow (its packet throttle). Tracking is a few
  // kB/s whatever happens, and a round trip that grows because a process was busy says nothing
  // about congestion; a dropped frame would only become missed tracking. So the throttle never
  // decelerates (both ends: ENet sends the setting to the peer too).
  enet_peer_throttle_configure(peer, ENET_PEER_PACKET_THROTTLE_INTERVAL,
                               ENET_PEER_PACKET_THROTTLE_ACCELERATION, 0);
  return LinkEvent::connected(slot.id);
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
    Slot* slot = slot_of(event.peer);
    // Ours: a slot this link still holds, for the same connection (a disconnect may come before
    // ENet has told us the connect ID).
    const bool ours = slot != nullptr && slot->id != kNoPeer &&
                      (event.peer->connectID == slot->connect_id ||
                       event.type == ENET_EVENT_TYPE_DISCONNECT || !slot->connected);
    switch (event.type) {
      case ENET_EVENT_TYPE_CONNECT:
        if (is_host_ && slot != nullptr) {
          const PeerId id = adopt(event.peer);
          return on_connected(event.peer, slots_[index_of(id)]);
        }
        if (!is_host_ && ours) {
          slot->connect_id = event.peer->connectID;
          return on_connected(event.peer, *slot);
        }
        enet_peer_reset(event.peer);
        break;
      case ENET_EVENT_TYPE_DISCONNECT:
        if (ours) {
          const PeerId id = slot->id;
          *slot = Slot{};
          return LinkEvent::disconnected(id, event.data);
        }
        break;
      case ENET_EVENT_TYPE_RECEIVE:
        if (ours && slot->connected && event.channelID < kChannelCount) {
          held_ = event.packet;
          return LinkEvent::received(
              slot->id, static_cast<Channel>(event.channelID),
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
