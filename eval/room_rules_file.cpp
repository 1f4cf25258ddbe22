#include "eval/room_rules_file.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/error.h"

namespace deixis::eval {
namespace {

using nlohmann::json;
using ordered_json = nlohmann::ordered_json;

constexpr std::uintmax_t kMaxFileBytes = 64 * 1024;

// A range field of RoomRules and the bounds any of its values must keep to (metres): wide enough
// for any room a person stands in, narrow enough that the generator's geometry stays meaningful.
struct RangeField {
  const char* name;
  float RoomRules::*min;
  float RoomRules::*max;
  float lowest, highest;
};
constexpr RangeField kRanges[] = {
    {"spot_distance", &RoomRules::spot_distance_min, &RoomRules::spot_distance_max, 0.5f, 10.0f},
    {"point_distance", &RoomRules::point_distance_min, &RoomRules::point_distance_max, 0.2f, 20.0f},
    {"point_height", &RoomRules::point_height_min, &RoomRules::point_height_max, 0.0f, 4.0f},
    {"touch_side", &RoomRules::touch_side_min, &RoomRules::touch_side_max, 0.0f, 1.0f},
    {"touch_forward", &RoomRules::touch_forward_min, &RoomRules::touch_forward_max, 0.0f, 1.0f},
    {"touch_height", &RoomRules::touch_height_min, &RoomRules::touch_height_max, 0.3f, 2.0f},
};

struct ValueField {
  const char* name;
  float RoomRules::*value;
  float lowest, highest;
};
constexpr ValueField kValues[] = {
    {"between_margin", &RoomRules::between_margin, 0.0f, 2.0f},
    {"point_azimuth_min_deg", &RoomRules::point_azimuth_min_deg, 0.0f, 89.0f},
    {"min_separation", &RoomRules::min_separation, 0.0f, 2.0f},
};

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& what) {
  throw Error(file.string() + ": " + what);
}

void check_size(std::uintmax_t bytes, const std::filesystem::path& file) {
  if (bytes > kMaxFileBytes) {
    fail(file, "larger than " + std::to_string(kMaxFileBytes) + " bytes");
  }
}

float number(const std::filesystem::path& file, const std::string& field, const json& v,
             float lowest, float highest) {
  if (!v.is_number()) {
    fail(file, field + ": not a number");
  }
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < static_cast<double>(lowest) || d > static_cast<double>(highest)) {
    std::ostringstream s;
    s << field << ": " << v.dump() << " is outside [" << lowest << ", " << highest << "]";
    fail(file, s.str());
  }
  return static_cast<float>(d);
}

json parse(std::string_view text, const std::filesystem::path& file) {
  check_size(text.size(), file);
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    fail(file, "not a JSON object");
  }
  // Compared as JSON values: `value("format", "")` would throw for a format that is not a string.
  const auto field = [&j](const char* key) { return j.contains(key) ? j[key] : json(); };
  if (field("format") != json("deixis-room-rules") || field("version") != json(1)) {
    fail(file, R"(expected "format": "deixis-room-rules", "version": 1)");
  }
  return j;
}

}  // namespace

RoomRules read_room_rules(const std::filesystem::path& file) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(file, ec);
  if (ec) {
    fail(file, "cannot read: " + ec.message());
  }
  check_size(size, file);  // before reading: a huge file is refused, not read
  std::ifstream in(file, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (!in) {
    fail(file, "cannot read");
  }
  return parse_room_rules(text, file);
}

RoomRules parse_room_rules(std::string_view text, const std::filesystem::path& file) {
  const json j = parse(text, file);
  RoomRules rules;
  for (const auto& [key, v] : j.items()) {
    if (key == "format" || key == "version") {
      continue;
    }
    bool known = false;
    for (const RangeField& f : kRanges) {
      if (key == f.name) {
        known = true;
        if (!v.is_array() || v.size() != 2) {
          fail(file, key + ": expected [min, max]");
        }
        rules.*f.min = number(file, key + "[0]", v[0], f.lowest, f.highest);
        rules.*f.max = number(file, key + "[1]", v[1], f.lowest, f.highest);
        if (rules.*f.min > rules.*f.max) {
          fail(file, key + ": minimum above maximum");
        }
      }
    }
    for (const ValueField& f : kValues) {
      if (key == f.name) {
        known = true;
        rules.*f.value = number(file, key, v, f.lowest, f.highest);
      }
    }
    if (!known) {
      fail(file, "unknown field '" + key + "'");
    }
  }
  return rules;
}

std::string room_rules_json(const RoomRules& rules) {
  // To the millimetre (or thousandth of a degree): what a person would write, not 0.899999976.
  const auto rounded = [](float v) { return std::round(static_cast<double>(v) * 1000.0) / 1000.0; };
  ordered_json j = {{"format", "deixis-room-rules"}, {"version", 1}};
  for (const RangeField& f : kRanges) {
    j[f.name] = {rounded(rules.*f.min), rounded(rules.*f.max)};
  }
  for (const ValueField& f : kValues) {
    j[f.name] = rounded(rules.*f.value);
  }
  return j.dump();
}

}  // namespace deixis::eval
