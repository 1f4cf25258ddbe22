#pragma once
// An in-process network between a host and a joiner, with the conditions of a real one: loss,
// delay, Gaussian jitter, reordering and duplicates, drawn from a seeded generator on a clock the
// caller sets (set_time). Unreliable packets (tracking) suffer all of them; reliable packets
// arrive once and in order, late by a retransmission for each loss, as ENet's would. A partition
// drops everything until it heals. A connection's PeerId is its attempt number, the same at both
// ends; a host with a connection turns a second one away (busy), as only one joiner exists here
// (the many-peer host is tested over real ENet). Used by the conditions matrix, the session tests
// and demos that want two sites in one process; the session cannot tell it from EnetLink.
//
// Fixed capacity: after construction, packets up to kSlotBytes move without allocating.

#include <cstddef>
#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include "net/link.h"

namespace deixis::net {

struct LinkConditions {
  double loss = 0.0;     // probability that a packet is lost (reliable ones are resent)
  double delay = 0.020;  // s, one way
  double jitter = 0.0;   // s, standard deviation of a Gaussian added to each delay (≥ 0 total)
  double reorder = 0.0;  // probability that a packet is held back by reorder_delay
  double reorder_delay = 0.050;  // s
  double duplicate = 0.0;        // probability that an unreliable packet arrives twice
};

struct SimulatedStats {
  std::uint64_t sent = 0;
  std::uint64_t lost = 0;
  std::uint64_t duplicated = 0;
  std::uint64_t reordered = 0;  // held back by reorder_delay
  std::uint64_t delivered = 0;
  std::uint64_t overflow = 0;  // dropped because every in-flight slot was taken
};

class SimulatedNetwork {
 public:
  enum class Side : std::uint8_t { kHost = 0, kJoiner = 1 };
  static constexpr std::size_t kSlots = 1024;
  static constexpr std::size_t kSlotBytes = 256;

  SimulatedNetwork(const LinkConditions& conditions, std::uint64_t seed);
  SimulatedNetwork(const SimulatedNetwork&) = delete;
  SimulatedNetwork& operator=(const SimulatedNetwork&) = delete;

  Link& host() { return links_[0]; }
  Link& joiner() { return links_[1]; }

  void set_time(double now) { now_ = now; }
  double now() const { return now_; }
  void set_conditions(const LinkConditions& conditions) { conditions_ = conditions; }
  // While partitioned nothing gets through: packets, connection attempts, disconnect notices.
  void set_partitioned(bool partitioned) { partitioned_ = partitioned; }
  // A packet from outside the session (a test's hostile peer): delivered to `to` after the delay.
  void inject(Side to, Channel channel, std::span<const std::byte> packet);
  // A disconnect notice from outside (spoofed disconnect data): delivered to `to` as if its peer
  // had closed the current connection with `code`.
  void inject_disconnect(Side to, std::uint32_t code);

  const SimulatedStats& stats() const { return stats_; }

 private:
  class End : public Link {
   public:
    End(SimulatedNetwork& net, Side side) : net_(&net), side_(side) {}
    PeerId connect() override { return net_->connect(side_); }
    void disconnect(PeerId peer, std::uint32_t code) override {
      net_->disconnect(side_, peer, code);
    }
    bool send(PeerId peer, Channel channel, std::span<const std::byte> packet) override {
      return net_->send(side_, peer, channel, packet);
    }
    LinkEvent next_event(std::uint32_t) override { return net_->next_event(side_); }
    std::string_view peer_name(PeerId) const override {
      return side_ == Side::kHost ? "sim:joiner" : "sim:host";
    }
    std::uint32_t peer_address(PeerId) const override {
      return side_ == Side::kHost ? 1u : 2u;  // one address per side
    }
    std::uint32_t round_trip_ms(PeerId) const override;

   private:
    SimulatedNetwork* net_;
    Side side_;
  };

  struct InFlight {
    bool active = false;
    double deliver_at = 0.0;
    std::uint64_t order = 0;  // ties at equal times keep sending order
    Side to = Side::kHost;
    LinkEvent::Kind kind = LinkEvent::Kind::kNone;
    Channel channel = Channel::kReliable;
    std::uint32_t data = 0;
    std::uint64_t connection = 0;  // the connection it belongs to
    std::vector<std::byte> bytes;
  };

  struct EndState {
    bool connected = false;
    std::uint64_t connection = 0;    // the connection this end is in, when connected
    double last_reliable_at = 0.0;   // reliable packets towards this end arrive in order
    std::vector<std::byte> current;  // the packet handed out by next_event()
  };

  PeerId connect(Side side);
  void disconnect(Side side, PeerId peer, std::uint32_t code);
  bool send(Side from, PeerId peer, Channel channel, std::span<const std::byte> packet);
  LinkEvent next_event(Side side);
  void enqueue(Side to, LinkEvent::Kind kind, Channel channel, double at, std::uint32_t data,
               std::uint64_t connection, std::span<const std::byte> bytes);
  // What an arriving event means to its end now; kNone when it is stale.
  LinkEvent deliver(Side side, InFlight& f);
  double one_way_delay();
  bool chance(double p);
  EndState& state(Side side) { return ends_[static_cast<std::size_t>(side)]; }
  static Side other(Side side) { return side == Side::kHost ? Side::kJoiner : Side::kHost; }

  LinkConditions conditions_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> gaussian_{0.0, 1.0};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  double now_ = 0.0;
  bool partitioned_ = false;
  std::uint64_t connection_ = 0;  // +1 per attempt; stale packets die with their connection
  bool connecting_ = false;       // the joiner's attempt `connection_` is in flight
  std::uint64_t order_ = 0;
  End links_[2];
  EndState ends_[2];
  std::vector<InFlight> in_flight_;
  SimulatedStats stats_;
};

}  // namespace deixis::net
