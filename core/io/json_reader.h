#pragma once
// Reading validated JSON documents (target maps, site configurations, input scripts): every error
// names the document and the path of the bad field, e.g. "rooms/b.json: objects[3].position[1]:
// not a finite number". Include only where a JSON format is parsed (nlohmann/json is slow to
// compile).
//
// The documents come from files, so nothing in them is trusted: the size and nesting depth are
// bounded before parsing and a key given twice is an error (core/io/json_guard.h), integers are
// range-checked whatever their sign, and names follow the wire's rules (core/io/text_rules.h).

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/io/json_guard.h"
#include "core/io/text_rules.h"
#include "core/math/pose.h"

namespace deixis {

class JsonReader {
 public:
  using json = nlohmann::json;

  explicit JsonReader(std::string_view source) : source_(source) {}

  // A whole file, at most kMaxJsonFileBytes; errors name the file.
  static std::string read_file(const std::filesystem::path& path) {
    try {
      return read_bounded_file(path);
    } catch (const JsonGuardError& e) {
      throw Error(path.string() + ": " + e.what());
    }
  }

  // Parses a whole document that must be a JSON object (size, depth and duplicate keys checked).
  json parse_object(std::string_view text) const {
    json j;
    try {
      j = parse_guarded_json(text);
    } catch (const JsonGuardError& e) {
      fail("", e.what());
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

  // An integer in [low, high]. nlohmann keeps non-negative integers as unsigned 64-bit values:
  // one above INT64_MAX must be refused as it is, not read as the negative number it wraps to.
  std::int64_t integer_in(const json& j, const std::string& path, std::int64_t low,
                          std::int64_t high) const {
    bool in_range = false;
    if (j.is_number_unsigned()) {
      const std::uint64_t v = j.get<std::uint64_t>();
      in_range = high >= 0 && v <= static_cast<std::uint64_t>(high) &&
                 (low <= 0 || v >= static_cast<std::uint64_t>(low));
    } else if (j.is_number_integer()) {
      const std::int64_t v = j.get<std::int64_t>();
      in_range = v >= low && v <= high;
    }
    if (!in_range) {
      fail(path, "expected an integer from " + std::to_string(low) + " to " + std::to_string(high) +
                     ", found " + describe(j));
    }
    return j.get<std::int64_t>();
  }

  // A name that goes on the wire (site, object or avatar model name): min_bytes to 64 bytes of
  // UTF-8 without control characters, the rules net/ enforces when it sends the name.
  std::string name(const json& j, const std::string& path, std::size_t min_bytes = 1) const {
    std::string s = string(j, path);
    if (s.size() < min_bytes || s.size() > kMaxNameBytes) {
      fail(path, "expected " + std::to_string(min_bytes) + " to " + std::to_string(kMaxNameBytes) +
                     " bytes, found " + std::to_string(s.size()));
    }
    if (!is_wire_text(s)) {
      fail(path, "not valid UTF-8 text without control characters");
    }
    return s;
  }

  Vec3 vec3(const json& j, const std::string& path) const {
    if (!j.is_array() || j.size() != 3) {
      fail(path, "expected [x, y, z]");
    }
    return {finite_number(j[0], path + "[0]"), finite_number(j[1], path + "[1]"),
            finite_number(j[2], path + "[2]")};
  }

 private:
  // A short description of a found value for messages (never the whole of a large value).
  static std::string describe(const json& j) {
    if (j.is_number()) {
      return j.dump();
    }
    return std::string("a ") + j.type_name();
  }

  std::string source_;
};

}  // namespace deixis
