// libFuzzer target for parse_target_map (core/target_map.h), which reads a room's target map
// from a file that may come from anywhere and whose names later go on the wire: every input must
// either parse into a map whose objects and names the wire accepts, or be refused with a
// deixis::Error naming the file. Seeds (fuzz/corpus/target_map/): the demo rooms and hostile files
// (deep nesting, duplicate keys, integers past INT64_MAX, bad name text).

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/io/text_rules.h"
#include "core/target_map.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "target_map_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const deixis::TargetMap map = deixis::parse_target_map(text, "fuzz-input.json");
    check(map.site.size() <= deixis::kMaxNameBytes && deixis::is_wire_text(map.site),
          "the site name is wire text");
    std::set<deixis::TargetId> ids;
    for (const deixis::TargetObject& o : map.objects) {
      check(
          !o.name.empty() && o.name.size() <= deixis::kMaxNameBytes && deixis::is_wire_text(o.name),
          "object names are wire text");
      check(ids.insert(o.id).second, "ids are unique");
      check(o.position.allFinite() && o.size.allFinite(), "numbers are finite");
    }
    // What is sent or saved must parse again to the same map.
    check(deixis::parse_target_map(deixis::to_json(map), "again").objects.size() ==
              map.objects.size(),
          "a parsed map round-trips");
  } catch (const deixis::Error& e) {
    check(std::string(e.what()).rfind("fuzz-input.json: ", 0) == 0, "errors name the file");
  }
  return 0;
}
