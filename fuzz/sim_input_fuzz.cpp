// libFuzzer target for parse_input_script (sim/sim_input.h), the scripted input of `deixis sim
// --input FILE`: every input must either parse into a bounded, time-ordered list of events that
// plays without error, or be refused with a deixis::Error naming the file. Seeds
// (fuzz/corpus/sim_input/): a click, a drag, keys and text, and hostile files (deep nesting,
// duplicate keys, huge integers, drags that expand past the event bound).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.h"
#include "sim/sim_input.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "sim_input_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const std::vector<deixis::sim::InputEvent> events =
        deixis::sim::parse_input_script(text, "fuzz-input.json");
    check(events.size() <= 220'000, "the expansion is bounded");
    for (std::size_t i = 1; i < events.size(); ++i) {
      check(events[i - 1].time <= events[i].time, "events are in time order");
    }
    // Play it: every widget is found at the origin.
    deixis::sim::ScriptedInput input(events);
    const deixis::sim::FindWidget anywhere = [](std::string_view) {
      return std::optional<deixis::render::Vec2>(deixis::render::Vec2(0, 0));
    };
    for (double t = 0.0; t <= 90000.0; t = t * 2.0 + 0.05) {
      input.next(t, anywhere);
    }
  } catch (const deixis::Error& e) {
    check(std::string(e.what()).rfind("fuzz-input.json: ", 0) == 0, "errors name the file");
  }
  return 0;
}
