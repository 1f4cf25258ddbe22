// libFuzzer target for a room member (net/room_session.h) hearing a hostile relay: the input is a
// script of relay callbacks with bytes the fuzzer chooses (room params, announces, member ids,
// payloads on either channel), clock steps, and well-formed helpers (a valid open or sealed room,
// a valid announce, a plain hello or tracking frame from a member) so that the fuzzer reaches the
// states past them. Byte 0 bit 0: this member has a passphrase. Then records, each an op byte:
//   0 ready | 1 entered(self, params, members) | 2 joined(id, announce) | 3 left(id)
//   4 payload(from, channel, bytes) | 5 poll(dt) | 6 relay lost | 7 send tracking and play out
//   8 entered a valid room (self) | 9 joined with a valid announce (id) | 10 a plain hello from
//   id | 11 a plain tracking frame from id (sequence) | 12 leave
// Whatever arrives, nothing crashes, people are verified members with a hello, each listed once,
// every event names a person 1–254, and every frame played is finite.

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "net/room_keys.h"
#include "net/room_session.h"
#include "net/tracking_codec.h"

namespace {

using namespace deixis;
using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "room_session_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

// Sends go nowhere: the fuzzer plays the relay and every other member.
class NoTransport final : public RoomTransport {
 public:
  bool enter(std::span<const std::uint8_t>, std::span<const std::uint8_t>) override { return true; }
  bool send(MemberId, Channel, std::span<const std::uint8_t> payload) override {
    check(!payload.empty() && payload.size() <= kRelayPayloadMax, "payloads fit a forward");
    return true;
  }
};

RoomConfig config(const std::string& site, const std::string& passphrase) {
  RoomConfig c;
  c.hello.site = site;
  c.hello.avatar.body.T_world_root.translation = Vec3(0, 1.6f, 0);
  c.target_map.site = site;
  c.passphrase = passphrase;
  c.kdf = c.min_kdf = {1, 8};
  c.derive_on_this_thread = true;  // results must not depend on a thread's timing
  c.max_members = 8;
  static const auto quiet = std::make_shared<spdlog::logger>("room_session_fuzz");
  c.logger = quiet;
  return c;
}

// Reads the script, bounded: past the end every read gives 0 and an empty span.
class Script {
 public:
  explicit Script(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  bool done() const { return at_ >= bytes_.size(); }
  std::uint8_t byte() { return done() ? 0 : bytes_[at_++]; }
  std::span<const std::uint8_t> take(std::size_t n) {
    n = std::min(n, bytes_.size() - std::min(at_, bytes_.size()));
    const auto out = bytes_.subspan(std::min(at_, bytes_.size()), n);
    at_ += n;
    return out;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

std::vector<std::uint8_t> encoded(const RoomParams& p) {
  std::vector<std::uint8_t> out(kRoomParamsBytes);
  encode(p, std::as_writable_bytes(std::span(out)));
  return out;
}

std::vector<std::uint8_t> valid_announce(bool passphrase) {
  const Entry e = make_entry(passphrase ? AuthMode::kPassphrase : AuthMode::kOpen);
  std::vector<std::uint8_t> out(kAnnounceBytes);
  encode(e.announce, std::as_writable_bytes(std::span(out)));
  return out;
}

std::vector<std::uint8_t> plain_hello(std::uint8_t id) {
  Hello h;
  std::array<char, 8> name{};
  std::snprintf(name.data(), name.size(), "M%u", static_cast<unsigned>(id));
  h.site = name.data();
  h.avatar.body.T_world_root.translation = Vec3(0.1f * id, 1.5f, 0);
  std::vector<std::byte> bytes;
  encode(h, bytes);
  const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
  return {p, p + bytes.size()};
}

std::vector<std::uint8_t> plain_tracking(std::uint32_t sequence, std::uint8_t id) {
  TrackingMessage m;
  m.sequence = sequence;
  m.frame.time = sequence / 30.0;
  m.frame.valid = tracked::kHead;
  m.frame.T_world_head.translation = Vec3(0.1f * id, 1.5f, 0);
  std::vector<std::uint8_t> out(kTrackingBytes);
  encode_tracking(m, Vec3(0.1f * id, 1.5f, 0), std::as_writable_bytes(std::span(out)));
  return out;
}

void check_people(RoomSession& room, double now) {
  const auto people = room.people();
  for (std::size_t i = 0; i < people.size(); ++i) {
    check(people[i] != kNoMember && people[i] != kAllMembers, "people have member ids");
    check(room.hello(people[i]) != nullptr, "people have said hello");
    check(std::count(people.begin(), people.end(), people[i]) == 1, "people listed once");
    for (Playout p = room.next_playout(people[i], now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
         p = room.next_playout(people[i], now)) {
      if (p.kind == PlayoutKind::kFrame) {
        check(p.frame != nullptr && p.frame->T_world_head.translation.allFinite(),
              "frames played are finite");
      }
    }
  }
  check(room.members() <= room.config().max_members, "members held within the bound");
  for (RoomEvent e; room.next_event(e);) {
    check(e.person >= kFirstMember && e.person <= kLastMember, "events name a person");
  }
}

void run(Script& s, bool passphrase) {
  NoTransport transport;
  const std::string site = "F";
  const std::string secret = passphrase ? "fuzz" : "";
  RoomSession room(transport, config(site, secret));
  double now = 0.0;
  std::uint32_t sent = 0;
  room.poll(now);
  for (int ops = 0; !s.done() && ops < 512; ++ops) {
    const std::uint8_t op = s.byte() % 13;
    switch (op) {
      case 0:
        room.on_relay_ready();
        break;
      case 1: {
        const MemberId self = s.byte();
        const auto params = s.take(s.byte() % 40);
        std::vector<RoomMember> there(s.byte() % 4);
        for (RoomMember& m : there) {
          m.id = s.byte();
          m.announce = s.take(s.byte() % 80);
        }
        room.on_entered(self, params, there);
        break;
      }
      case 2: {
        const MemberId id = s.byte();
        room.on_member_joined({id, s.take(s.byte() % 80)});
        break;
      }
      case 3:
        room.on_member_left(s.byte());
        break;
      case 4: {
        const MemberId from = s.byte();
        const Channel channel = (s.byte() & 1) != 0 ? Channel::kTracking : Channel::kReliable;
        const std::size_t n = s.byte() * 8u + s.byte();
        room.on_payload(from, channel, s.take(n));
        break;
      }
      case 5:
        now += s.byte() / 50.0;
        room.poll(now);
        break;
      case 6:
        room.on_relay_lost();
        break;
      case 7:
        room.send_tracking(TrackingFrame{}, static_cast<double>(sent++) / 30.0);
        break;
      case 8: {
        room.on_relay_ready();
        const MemberId self = s.byte();
        const auto params = encoded(make_room_params(passphrase, {1, 8}));
        room.on_entered(self, params, {});
        break;
      }
      case 9: {
        const MemberId id = s.byte();
        const auto announce = valid_announce(passphrase);
        room.on_member_joined({id, announce});
        break;
      }
      case 10: {
        const MemberId id = s.byte();
        const auto hello = plain_hello(id);
        room.on_payload(id, Channel::kReliable, hello);
        break;
      }
      case 11: {
        const MemberId id = s.byte();
        const auto frame = plain_tracking(s.byte(), id);
        room.on_payload(id, Channel::kTracking, frame);
        break;
      }
      default:
        room.leave(now);
        break;
    }
    check_people(room, now);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  Script s(std::span(data, size).subspan(1));
  run(s, (data[0] & 1) != 0);
  return 0;
}
