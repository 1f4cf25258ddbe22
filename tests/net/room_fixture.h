#pragma once
// An in-process relay with the semantics of net/relay_client.h, for the room tests: members enter
// one room, get ids 1–254 (fresh for every entry), the first member's params stay the room's,
// the others hear who joined and left, and payloads are forwarded with their channel and the
// sender's id, never parsed. Everything is delivered on the test's clock, after each sender's
// latency (and, for tracking, jitter and loss on its own uplink), so one member's bad link
// affects only its own stream. Hooks let a test play a hostile relay: see, change, drop or
// inject forwards. Its slots are reused, so a stable room allocates nothing in here either.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "net/room_session.h"
#include "net_fixtures.h"

namespace deixis::testing {

using net::Channel;
using net::MemberId;

class FakeRelay {
 public:
  struct Uplink {
    double latency = 0.010;      // s, every message from this member
    double jitter = 0.0;         // s, uniform extra on tracking forwards
    double tracking_loss = 0.0;  // share of its tracking forwards dropped
    bool blocked = false;        // everything it sends is lost (it stays in the room)
  };

  // One member's connection: what a RoomSession sends through.
  class Endpoint final : public net::RoomTransport {
   public:
    Endpoint(FakeRelay& relay, std::size_t /*index*/) : relay_(relay) {}
    bool enter(std::span<const std::uint8_t> params,
               std::span<const std::uint8_t> announce) override {
      return relay_.enter(*this, params, announce);
    }
    bool send(MemberId to, Channel channel, std::span<const std::uint8_t> payload) override {
      return relay_.forward(*this, to, channel, payload);
    }
    MemberId id() const { return id_; }
    bool in_room() const { return in_room_; }
    Uplink uplink;
    net::RelayListener* listener = nullptr;
    std::uint64_t payloads_received = 0;
    std::array<std::uint64_t, 256> received_by_type{};  // first byte of each payload delivered

   private:
    friend class FakeRelay;
    FakeRelay& relay_;
    MemberId id_ = net::kNoMember;
    bool in_room_ = false;
    bool connected_ = false;
    std::vector<std::uint8_t> announce_;
  };

  // A forward as the relay holds it; hooks may change `from` and `bytes` or drop it.
  struct Forward {
    MemberId from = net::kNoMember;
    Endpoint* to = nullptr;
    Channel channel = Channel::kReliable;
    std::vector<std::uint8_t> bytes;
  };
  // Called for each forward before it is queued; false drops it.
  std::function<bool(Forward&)> on_forward;
  // Called on each announce as the relay keeps it for the others (a relay that changes them).
  std::function<void(std::vector<std::uint8_t>&)> on_announce;

  explicit FakeRelay(std::uint64_t seed = 1) : random_(seed) {
    items_.resize(4096);
    for (Item& it : items_) {
      it.bytes.reserve(1024);  // a sealed tracking frame, heartbeat or padded hello fits
    }
    due_.reserve(items_.size());
  }

  Endpoint& add() {
    endpoints_.push_back(std::make_unique<Endpoint>(*this, endpoints_.size()));
    return *endpoints_.back();
  }
  // The client reaches the relay: on_relay_ready after its latency.
  void connect(Endpoint& e) {
    e.connected_ = true;
    queue(Kind::kReady, e, net::kNoMember, Channel::kReliable, {}, e.uplink.latency);
  }
  // The client goes away (closed, or its connection dropped): the others hear it left.
  void disconnect(Endpoint& e) {
    e.connected_ = false;
    leave(e);
  }
  // The relay restarts: every client hears it lost, the room is forgotten, and the clients are
  // welcomed again after `down` seconds.
  void restart(double down) {
    for (auto& e : endpoints_) {
      if (!e->connected_) {
        continue;
      }
      e->in_room_ = false;
      e->id_ = net::kNoMember;
      queue(Kind::kLost, *e, net::kNoMember, Channel::kReliable, {}, 0.0);
      queue(Kind::kReady, *e, net::kNoMember, Channel::kReliable, {}, down);
    }
    params_.clear();
    for (Item& it : items_) {  // forwards in flight die with the relay
      it.used = it.used && (it.kind == Kind::kLost || it.kind == Kind::kReady);
    }
  }
  // A payload as if the relay forwarded it from `from` (a hostile relay, or a replay).
  void inject(Endpoint& to, MemberId from, Channel channel, std::span<const std::uint8_t> bytes) {
    queue(Kind::kPayload, to, from, channel, bytes, 0.0);
  }

  // Delivers everything due by `now`, in order.
  void deliver(double now) {
    now_ = now;
    due_.clear();
    for (std::size_t i = 0; i < items_.size(); ++i) {
      if (items_[i].used && items_[i].due <= now) {
        due_.push_back(i);
      }
    }
    std::sort(due_.begin(), due_.end(), [&](std::size_t a, std::size_t b) {
      return items_[a].due != items_[b].due ? items_[a].due < items_[b].due
                                            : items_[a].order < items_[b].order;
    });
    for (const std::size_t i : due_) {
      if (items_[i].used) {  // a restart may have dropped it meanwhile
        deliver(items_[i]);
        items_[i].used = false;
      }
    }
  }
  void set_time(double now) { now_ = now; }

  std::span<const std::uint8_t> params() const { return params_; }
  std::uint64_t forwards = 0;

 private:
  enum class Kind : std::uint8_t { kReady, kEntered, kJoined, kLeft, kPayload, kLost };
  struct Item {
    bool used = false;
    Kind kind = Kind::kPayload;
    Endpoint* to = nullptr;
    MemberId from = net::kNoMember;
    Channel channel = Channel::kReliable;
    std::vector<std::uint8_t> bytes;
    double due = 0.0;
    std::uint64_t order = 0;
    std::size_t split = 0;  // kEntered: the params' size, the members follow
  };

  Item& queue(Kind kind, Endpoint& to, MemberId from, Channel channel,
              std::span<const std::uint8_t> bytes, double delay) {
    for (std::size_t tries = 0; items_[cursor_].used; ++tries) {
      if (tries == items_.size()) {
        throw std::runtime_error("FakeRelay: every slot is in flight (is the clock moving?)");
      }
      cursor_ = (cursor_ + 1) % items_.size();
    }
    Item& it = items_[cursor_];
    it.used = true;
    it.kind = kind;
    it.to = &to;
    it.from = from;
    it.channel = channel;
    it.bytes.assign(bytes.begin(), bytes.end());
    it.due = now_ + delay;
    it.order = order_++;
    return it;
  }

  MemberId fresh_id() {
    for (;;) {
      next_id_ = next_id_ >= net::kLastMember ? net::kFirstMember : next_id_ + 1;
      const bool used = std::any_of(endpoints_.begin(), endpoints_.end(), [&](const auto& e) {
        return e->in_room_ && e->id_ == next_id_;
      });
      if (!used) {
        return next_id_;
      }
    }
  }

  bool enter(Endpoint& e, std::span<const std::uint8_t> params,
             std::span<const std::uint8_t> announce) {
    if (!e.connected_ || e.in_room_ || params.size() > net::kRoomParamsMax ||
        announce.size() > net::kAnnounceMax) {
      return false;
    }
    const bool empty = std::none_of(endpoints_.begin(), endpoints_.end(),
                                    [](const auto& m) { return m->in_room_; });
    if (empty) {
      params_.assign(params.begin(), params.end());
    }
    e.id_ = fresh_id();
    e.in_room_ = true;
    e.announce_.assign(announce.begin(), announce.end());
    if (on_announce) {
      on_announce(e.announce_);
    }
    // on_entered carries the room's params and everyone there, with their announces:
    // bytes = params, then per member: id, announce length, announce.
    std::vector<std::uint8_t> entered(params_);
    for (const auto& m : endpoints_) {
      if (m.get() != &e && m->in_room_) {
        entered.push_back(m->id_);
        entered.push_back(static_cast<std::uint8_t>(m->announce_.size()));
        entered.insert(entered.end(), m->announce_.begin(), m->announce_.end());
        queue(Kind::kJoined, *m, e.id_, Channel::kReliable, e.announce_, e.uplink.latency);
      }
    }
    Item& it = queue(Kind::kEntered, e, e.id_, Channel::kReliable, entered, e.uplink.latency);
    it.split = params_.size();
    return true;
  }

  void leave(Endpoint& e) {
    if (!e.in_room_) {
      return;
    }
    e.in_room_ = false;
    for (const auto& m : endpoints_) {
      if (m->in_room_) {
        queue(Kind::kLeft, *m, e.id_, Channel::kReliable, {}, e.uplink.latency);
      }
    }
    e.id_ = net::kNoMember;
  }

  bool forward(Endpoint& e, MemberId to, Channel channel, std::span<const std::uint8_t> payload) {
    if (!e.in_room_ || payload.empty() || payload.size() > net::kRelayPayloadMax) {
      return false;
    }
    for (const auto& m : endpoints_) {
      if (m.get() == &e || !m->in_room_ || (to != net::kAllMembers && m->id_ != to)) {
        continue;
      }
      if (e.uplink.blocked || (channel == Channel::kTracking && e.uplink.tracking_loss > 0.0 &&
                               uniform_(random_) < e.uplink.tracking_loss)) {
        continue;
      }
      double delay = e.uplink.latency;
      if (channel == Channel::kTracking) {
        delay += e.uplink.jitter * uniform_(random_);
      }
      ++forwards;
      if (on_forward) {
        scratch_.from = e.id_;
        scratch_.to = m.get();
        scratch_.channel = channel;
        scratch_.bytes.assign(payload.begin(), payload.end());
        if (!on_forward(scratch_)) {
          continue;
        }
        queue(Kind::kPayload, *scratch_.to, scratch_.from, scratch_.channel, scratch_.bytes, delay);
        continue;
      }
      queue(Kind::kPayload, *m, e.id_, channel, payload, delay);
    }
    return true;
  }

  void deliver(Item& it) {
    Endpoint& to = *it.to;
    if (to.listener == nullptr) {
      return;
    }
    switch (it.kind) {
      case Kind::kReady:
        if (to.connected_) {
          to.listener->on_relay_ready();
        }
        return;
      case Kind::kLost:
        to.listener->on_relay_lost();
        return;
      case Kind::kEntered: {
        if (!to.in_room_ || to.id_ != it.from) {
          return;  // it left meanwhile
        }
        const std::size_t params_size = it.split;
        const std::span<const std::uint8_t> all(it.bytes);
        std::vector<net::RoomMember> there;
        for (std::size_t at = params_size; at + 2 <= all.size();) {
          const std::size_t n = all[at + 1];
          there.push_back({all[at], all.subspan(at + 2, n)});
          at += 2 + n;
        }
        to.listener->on_entered(it.from, all.first(params_size), there);
        return;
      }
      case Kind::kJoined:
        if (to.in_room_) {
          to.listener->on_member_joined({it.from, it.bytes});
        }
        return;
      case Kind::kLeft:
        if (to.in_room_) {
          to.listener->on_member_left(it.from);
        }
        return;
      case Kind::kPayload:
        if (to.in_room_) {
          ++to.payloads_received;
          ++to.received_by_type[it.bytes.empty() ? 0 : it.bytes[0]];
          to.listener->on_payload(it.from, it.channel, it.bytes);
        }
        return;
    }
  }

  std::vector<std::unique_ptr<Endpoint>> endpoints_;
  std::vector<Item> items_;
  std::vector<std::size_t> due_;
  std::size_t cursor_ = 0;
  std::uint64_t order_ = 0;
  std::vector<std::uint8_t> params_;
  MemberId next_id_ = 0;
  double now_ = 0.0;
  Forward scratch_;
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// A room config for tests: the cheapest Argon2id on the calling thread (the protocol is under
// test here, not the KDF's cost; the floor is lowered to match).
inline net::RoomConfig room_config(const std::string& site, const std::string& passphrase,
                                   float height = 1.7f) {
  net::RoomConfig c;
  c.hello = make_hello(site, height);
  c.target_map = make_target_map(site, 3);
  c.passphrase = passphrase;
  c.kdf = {1, 8};
  c.min_kdf = {1, 8};
  c.derive_on_this_thread = true;
  return c;
}

// A relay and its members on one clock.
struct RoomHarness {
  FakeRelay relay;
  std::vector<FakeRelay::Endpoint*> endpoints;
  std::vector<std::unique_ptr<net::RoomSession>> members;
  double now = 0.0;

  explicit RoomHarness(std::uint64_t seed = 1) : relay(seed) {}

  // A member, connected at once (enters after the relay's latency).
  net::RoomSession& add(net::RoomConfig config, bool connect = true) {
    FakeRelay::Endpoint& e = relay.add();
    endpoints.push_back(&e);
    members.push_back(std::make_unique<net::RoomSession>(e, std::move(config)));
    e.listener = members.back().get();
    if (connect) {
      relay.connect(e);
    }
    return *members.back();
  }

  // One step: every member's timers at the new time, then what the relay has due.
  void step(double dt = 0.005) {
    now += dt;
    relay.set_time(now);
    for (auto& m : members) {
      m->poll(now);
    }
    relay.deliver(now);
  }

  bool run_until(const std::function<bool()>& done, double seconds, double dt = 0.005) {
    const double end = now + seconds;
    while (now < end) {
      if (done()) {
        return true;
      }
      step(dt);
    }
    return done();
  }

  // Every member of `who` sees exactly `n` people.
  bool everyone_sees(std::initializer_list<std::size_t> who, std::size_t n) const {
    return std::all_of(who.begin(), who.end(),
                       [&](std::size_t i) { return members[i]->people().size() == n; });
  }
};

}  // namespace deixis::testing
