// libFuzzer target for parse_bvh (mocap/bvh.h), which reads motion recordings from anywhere:
// every input must either parse into a hierarchy whose numbers are finite and whose motion has
// exactly frames x channels values, and whose written form parses back to the same file, or be
// refused with a deixis::Error naming the file and a line. When a skeleton with a head and hands
// is found, its tracking is finite. Seeds (fuzz/corpus/bvh/): small hand-written files and the
// head of a real CMU recording.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "core/error.h"
#include "mocap/bvh.h"
#include "mocap/skeleton_tracking.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "bvh_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace deixis::mocap;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  BvhLimits limits;
  limits.max_values = 1u << 20;  // keep each run small
  Bvh b;
  try {
    b = parse_bvh(text, "fuzz-input.bvh", limits);
  } catch (const deixis::Error& e) {
    check(std::string(e.what()).rfind("fuzz-input.bvh:", 0) == 0, "errors name the file");
    return 0;
  }
  check(!b.nodes.empty() && b.channels > 0, "a hierarchy with channels");
  check(b.motion.size() == b.frames() * b.channels && b.frames() >= 1, "frames x channels");
  check(b.frame_time > 0 && std::isfinite(b.frame_time), "frame time");
  for (const float v : b.motion) {
    check(std::isfinite(v), "finite values");
  }
  const Bvh again = parse_bvh(write_bvh(b), "again", limits);
  check(again.nodes.size() == b.nodes.size() && again.motion == b.motion, "round trip");
  try {
    SkeletonTracking tracking(b, 0.01);
    deixis::TrackingFrame f;
    tracking.track(b.frames() - 1, f);
  } catch (const deixis::Error&) {
    // A hierarchy without a head or hands.
  }
  return 0;
}
