#pragma once
// Reading validated JSON documents (target maps, site configurations): every error names the
// document and the path of the bad field, e.g. "rooms/b.json: objects[3].position[1]: not a
// finite number". Include only where a JSON format is parsed (nlohmann/json is slow to compile).

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "gesture/error.h"
#include "gesture/math/pose.h"

namespace deixis {

class JsonReader {
 public:
  using json = nlohmann::json;

  explicit JsonReader(std::string_view source) : source_(source) {}

  // Parses a whole document that must be a JSON object.
  json parse_object(std::string_view text) const {
    json j;
    try {
      j = json::parse(text);
    } catch (const json::exception& e) {  // parse errors and number overflows alike
      fail("", std::string("not valid JSON: ") + e.what());
    }
    if (!j.is_object()) {
      fail("", "expected a JSON object");
    }
    return j;
  }

  [[noreturn]] void fail(const std::string& path, const std::string& what) const {
    throw Error(source_ + ": " + (path.empty() ? "" : path + ": ") + what);
  }

  // Rejects fields other than `allowed` (typos should not be silently ignored).
  void only_fields(const json& object, const std::string& path,
                   std::initializer_list<std::string_view> allowed) const {
    for (const auto& [key, value] : object.items()) {
      bool known = false;
      for (const std::string_view a : allowed) {
        known |= key == a;
      }
      if (!known) {
        fail(path, "unknown field '" + key + "'");
      }
    }
  }

  const json& member(const json& object, const std::string& path, const char* key) const {
    if (!object.is_object()) {
      fail(path, "expected an object");
    }
    if (!object.contains(key)) {
      fail(path, std::string("missing field '") + key + "'");
    }
    return object[key];
  }

  static std::string child(const std::string& path, const char* key) {
    return path.empty() ? std::string(key) : path + "." + key;
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) {
      fail(path, std::string("expected a string, found ") + j.type_name());
    }
    return j.get<std::string>();
  }

  float finite_number(const json& j, const std::string& path) const {
    if (!j.is_number()) {
      fail(path, "not a finite number");
    }
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > 1e6) {
      fail(path, "not a finite number");
    }
    return static_cast<float>(v);
  }

  float number_in(const json& j, const std::string& path, float low, float high) const {
    const float v = finite_number(j, path);
    if (v < low || v > high) {
      fail(path, "expected a number in [" + std::to_string(low) + ", " + std::to_string(high) +
                     "], found " + std::to_string(v));
    }
    return v;
  }

  std::int64_t integer_in(const json& j, const std::string& path, std::int64_t low,
                          std::int64_t high) const {
    if (!j.is_number_integer() || j.get<std::int64_t>() < low || j.get<std::int64_t>() > high) {
      fail(path, "expected an integer from " + std::to_string(low) + " to " + std::to_string(high));
    }
    return j.get<std::int64_t>();
  }

  Vec3 vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) {
      fail(path, "expected [x, y, z]");
    }
    return {finite_number(j[0], path + "[0]"), finite_number(j[1], path + "[1]"),
            finite_number(j[2], path + "[2]")};
  }

 private:
  std::string source_;
};

}  // namespace deixis
