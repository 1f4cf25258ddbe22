// libFuzzer target for parse_room_rules (eval/room_rules_file.h), which reads the live
// evaluation's room rules from a file a user hands `deixis eval --live-rooms --rules`: every
// input must either parse into rules whose every value is finite, inside its documented bounds
// and whose ranges run from minimum to maximum, or be refused with a deixis::Error naming the
// file. Seeds (fuzz/corpus/room_rules/): the defaults, a partial file, hostile ones (wrong types,
// out-of-range numbers, deep nesting, duplicate keys).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "core/error.h"
#include "eval/room_rules_file.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "room_rules_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

void check_range(float lo, float hi, float lowest, float highest) {
  check(std::isfinite(lo) && std::isfinite(hi), "every value is finite");
  check(lo <= hi, "ranges run from minimum to maximum");
  check(lo >= lowest && hi <= highest, "values stay within their bounds");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const deixis::eval::RoomRules r = deixis::eval::parse_room_rules(text, "fuzz-input.json");
    check_range(r.spot_distance_min, r.spot_distance_max, 0.5f, 10.0f);
    check_range(r.point_distance_min, r.point_distance_max, 0.2f, 20.0f);
    check_range(r.point_height_min, r.point_height_max, 0.0f, 4.0f);
    check_range(r.touch_side_min, r.touch_side_max, 0.0f, 1.0f);
    check_range(r.touch_forward_min, r.touch_forward_max, 0.0f, 1.0f);
    check_range(r.touch_height_min, r.touch_height_max, 0.3f, 2.0f);
    check_range(r.between_margin, r.between_margin, 0.0f, 2.0f);
    check_range(r.point_azimuth_min_deg, r.point_azimuth_min_deg, 0.0f, 89.0f);
    check_range(r.min_separation, r.min_separation, 0.0f, 2.0f);
    // What a report prints reads back as the same rules.
    const std::string printed = deixis::eval::room_rules_json(r);
    check(deixis::eval::room_rules_json(deixis::eval::parse_room_rules(printed, "printed")) ==
              printed,
          "printed rules read back the same");
  } catch (const deixis::Error& e) {
    check(std::string_view(e.what()).find("fuzz-input.json") != std::string_view::npos,
          "a refusal names the file");
  }
  return 0;
}
