// libFuzzer target for the packet decoders of net/ (docs/protocol.md): every decoder gets every
// input. A decoder may reject (it returns a reason and a field, never throws or asserts) or
// accept; what it accepts must keep the protocol's promises:
//   - handshake, heartbeat, bye and target-map messages re-encode to exactly the input bytes;
//   - a hello passes validate() and survives re-encoding (its root quaternion up to rounding);
//   - a tracking frame is finite, its ids in range, and re-encoding it gives a frame within one
//     quantisation step of it.
// Built with libFuzzer by the `fuzz` preset; in ordinary builds net_packet_replay replays the
// committed corpus fuzz/corpus/net_packet/.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <span>
#include <vector>

#include "core/target_map.h"
#include "net/avatar_transfer.h"
#include "net/messages.h"
#include "net/quantize.h"
#include "net/tracking_codec.h"

namespace {

using namespace deixis;
using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "net_packet_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

void check_result(WireResult r) {
  check(r.reason != DropReason::kNone || r.field[0] == '\0', "success names no field");
  check(r.reason == DropReason::kNone || r.field[0] != '\0', "a rejection names its field");
  check(static_cast<std::size_t>(r.reason) < kDropReasonCount, "a known reason");
}

// Messages whose decoding loses nothing: encoding the result gives the input back.
template <typename Message>
void check_exact(std::span<const std::byte> input) {
  Message m;
  const WireResult r = decode(input, m);
  check_result(r);
  if (!r.ok()) {
    return;
  }
  std::vector<std::byte> again;
  if constexpr (std::is_same_v<Message, TargetMap>) {
    check(encode(m, again).ok(), "an accepted target map encodes");
  } else if constexpr (std::is_same_v<Message, Heartbeat> || std::is_same_v<Message, Bye>) {
    again.resize(16);
    again.resize(encode(m, again));
  } else {
    encode(m, again);
  }
  check(std::equal(again.begin(), again.end(), input.begin(), input.end()),
        "re-encoding an accepted message gives its bytes");
}

void check_hello(std::span<const std::byte> input) {
  Hello h;
  const WireResult r = decode(input, h);
  check_result(r);
  if (!r.ok()) {
    return;
  }
  check(validate(h).ok(), "an accepted hello is valid");
  std::vector<std::byte> again;
  check(encode(h, again).ok(), "an accepted hello encodes");
  Hello back;
  check(decode(again, back).ok(), "a re-encoded hello decodes");
  check(back.site == h.site && back.avatar.model == h.avatar.model &&
            back.avatar.body.height == h.avatar.body.height &&
            back.avatar.body.T_world_root.translation == h.avatar.body.T_world_root.translation,
        "a hello survives re-encoding");
  check((back.avatar.body.T_world_root.rotation - h.avatar.body.T_world_root.rotation)
                .cwiseAbs()
                .maxCoeff() < 1e-5f,
        "the root rotation survives re-encoding");
}

// Avatar requests and chunks: accepted ones keep their bounds and re-encode to their bytes.
void check_avatar(std::span<const std::byte> input) {
  std::vector<std::byte> again(kAvatarDataHeaderBytes + kAvatarChunkMaxBytes);
  AvatarRequest request;
  const WireResult r = decode(input, request);
  check_result(r);
  if (r.ok()) {
    const std::size_t n = encode(request, again);
    check(std::equal(again.begin(), again.begin() + static_cast<std::ptrdiff_t>(n), input.begin(),
                     input.end()),
          "an accepted avatar request re-encodes to its bytes");
  }
  AvatarData data;
  const WireResult d = decode(input, data);
  check_result(d);
  if (d.ok()) {
    check(data.total >= 1 && data.total <= kAvatarFileMaxBytes, "a file size within bounds");
    check(!data.bytes.empty() && data.bytes.size() <= kAvatarChunkMaxBytes &&
              data.offset < data.total && data.bytes.size() <= data.total - data.offset,
          "a chunk inside its file");
    const std::size_t n = encode(data, again);
    check(std::equal(again.begin(), again.begin() + static_cast<std::ptrdiff_t>(n), input.begin(),
                     input.end()),
          "an accepted avatar chunk re-encodes to its bytes");
  }
}

bool finite(const TrackingFrame& f) {
  return std::isfinite(f.time) && is_finite(f.T_world_head) && f.gaze.allFinite() &&
         is_finite(f.T_world_wrist[0]) && is_finite(f.T_world_wrist[1]) &&
         f.index_tip[0].allFinite() && f.index_tip[1].allFinite() &&
         f.head_target_position.allFinite() && f.hand_target_position.allFinite();
}

void check_tracking(std::span<const std::byte> input) {
  const Vec3 root(0.25f, 1.6f, -3.0f);
  TrackingMessage m;
  const WireResult r = decode_tracking(input, root, m);
  check_result(r);
  if (!r.ok()) {
    return;
  }
  const TrackingFrame& f = m.frame;
  check(input.size() == kTrackingBytes, "only whole tracking messages are accepted");
  check(finite(f), "an accepted frame is finite");
  check((f.valid & ~tracked::kAll) == 0, "only known validity bits");
  for (const TargetId id : {f.head_target, f.hand_target}) {
    check((id >= kNoTarget && id <= kMaxTargetIdOnWire) || is_person_target(id),
          "target ids in range");
  }
  check(std::abs(f.gaze.norm() - 1.0f) < 1e-5f, "gaze is a unit vector");
  for (const Pose* p : {&f.T_world_head, &f.T_world_wrist[0], &f.T_world_wrist[1]}) {
    check((p->rotation.transpose() * p->rotation - Mat3::Identity()).cwiseAbs().maxCoeff() < 1e-4f,
          "rotations are orthonormal");
  }
  // Re-encoding loses at most one more quantisation step.
  std::vector<std::byte> again(kTrackingBytes);
  const TrackingEncoding e = encode_tracking(m, root, again);
  check(e.bytes == kTrackingBytes, "an accepted frame re-encodes");
  check(e.dropped_parts == 0, "every part of an accepted frame can be sent again");
  TrackingMessage back;
  check(decode_tracking(again, root, back).ok(), "a re-encoded frame decodes");
  check(back.sequence == m.sequence && back.frame.valid == f.valid &&
            back.frame.head_target == f.head_target && back.frame.hand_target == f.hand_target,
        "sequence, flags and targets survive re-encoding");
  check((back.frame.T_world_head.translation - f.T_world_head.translation).norm() < 0.002f,
        "positions survive re-encoding within a step");
  check((back.frame.T_world_wrist[1].rotation - f.T_world_wrist[1].rotation).cwiseAbs().maxCoeff() <
            1e-3f,
        "rotations survive re-encoding within a step");
  check(std::abs(back.frame.time - f.time) < 1e-9, "time survives re-encoding");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> input =
      size == 0 ? std::span<const std::byte>()
                : std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size);
  try {
    check_exact<Welcome>(input);
    check_exact<Join>(input);
    check_exact<Accept>(input);
    check_exact<TargetMap>(input);
    check_exact<Heartbeat>(input);
    check_exact<Bye>(input);
    check_hello(input);
    check_tracking(input);
    check_avatar(input);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "net_packet_fuzz: a decoder threw: %s\n", e.what());
    __builtin_trap();
  }
  return 0;
}
