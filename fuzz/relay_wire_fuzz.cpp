// libFuzzer target for the relay's decoders (net/relay_wire.h, docs/relay.md): every decoder gets
// every input. A decoder may reject (a reason and a field, never a throw or an assert) or accept;
// what it accepts must keep the wire's promises: lengths and ids within their bounds, spans
// inside the input, and re-encoding gives exactly the input bytes. Built with libFuzzer by the
// `fuzz` preset; in ordinary builds relay_wire_replay replays fuzz/corpus/relay_wire/.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <vector>

#include "net/relay_wire.h"

namespace {

using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "relay_wire_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

void check_result(WireResult r) {
  check(r.reason != DropReason::kNone || r.field[0] == '\0', "success names no field");
  check(r.reason == DropReason::kNone || r.field[0] != '\0', "a rejection names its field");
  check(static_cast<std::size_t>(r.reason) < kDropReasonCount, "a known reason");
}

bool inside(std::span<const std::uint8_t> part, std::span<const std::byte> whole) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(whole.data());
  return part.empty() || (part.data() >= b && part.data() + part.size() <= b + whole.size());
}

bool is_member(MemberId id) {
  return id >= kFirstMember && id <= kLastMember;
}

// Accepted messages re-encode to the input, byte for byte.
template <typename Message, typename Check>
void check_exact(std::span<const std::byte> input, Check&& holds) {
  Message m;
  const WireResult r = decode(input, m);
  check_result(r);
  if (!r.ok()) {
    return;
  }
  holds(m);
  std::vector<std::byte> again(kMaxPacketBytes);
  again.resize(encode(m, again));
  check(again.size() == input.size() &&
            std::equal(again.begin(), again.end(), input.begin(), input.end()),
        "an accepted message re-encodes to its bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> input(reinterpret_cast<const std::byte*>(data), size);
  check_exact<RelayWelcome>(input, [](const RelayWelcome& m) {
    check(m.max_people >= 2 && m.max_people <= kMaxRoomPeople, "welcome: max people in range");
  });
  check_exact<RelayEnter>(input, [&](const RelayEnter& m) {
    check(m.params.size() <= kRoomParamsMax && m.announce.size() <= kAnnounceMax,
          "enter: lengths bounded");
    check(inside(m.params, input) && inside(m.announce, input), "enter: spans in the input");
  });
  check_exact<RelayEntered>(input, [&](const RelayEntered& m) {
    check(is_member(m.self), "entered: self is a member id");
    check(m.count < kMaxRoomPeople && m.params.size() <= kRoomParamsMax, "entered: bounded");
    for (std::size_t i = 0; i < m.count; ++i) {
      check(is_member(m.members[i].id) && m.members[i].id != m.self, "entered: member ids");
      check(m.members[i].announce.size() <= kAnnounceMax && inside(m.members[i].announce, input),
            "entered: announces bounded and in the input");
    }
  });
  check_exact<RelayJoined>(input, [&](const RelayJoined& m) {
    check(is_member(m.member.id) && m.member.announce.size() <= kAnnounceMax,
          "joined: id and announce");
  });
  check_exact<RelayLeft>(input, [](const RelayLeft& m) { check(is_member(m.id), "left: id"); });
  check_exact<RelayRefused>(input, [](const RelayRefused& m) {
    check(static_cast<std::uint8_t>(m.reason) <= kMaxRelayRefusal, "refused: a known reason");
  });
  {
    RelayForward m;
    const WireResult r = decode(input, m);
    check_result(r);
    if (r.ok()) {
      check(is_member(m.to) || m.to == kAllMembers, "forward: to a member or everyone");
      check(!m.payload.empty() && m.payload.size() <= kRelayPayloadMax, "forward: payload size");
      std::vector<std::byte> again(kMaxPacketBytes);
      again.resize(encode_forward(m.to, m.payload, again));
      check(std::equal(again.begin(), again.end(), input.begin(), input.end()),
            "forward re-encodes");
      // What the relay makes of it is a valid forwarded message.
      again.assign(kMaxPacketBytes, std::byte{0});
      again.resize(encode_forwarded(kFirstMember, m.payload, again));
      RelayForwarded f;
      check(decode(again, f).ok() && f.payload.size() == m.payload.size(),
            "the forwarded copy decodes");
    }
  }
  {
    RelayForwarded m;
    const WireResult r = decode(input, m);
    check_result(r);
    if (r.ok()) {
      check(is_member(m.from), "forwarded: from a member");
    }
  }
  check_result(decode_keepalive(input));
  for (int type = 0; type < 256; ++type) {
    const auto t = static_cast<std::uint8_t>(type);
    check(!is_relay_type(t) || (t >= kRelayTypeFirst && t <= kRelayTypeLast), "relay types");
  }
  return 0;
}
