#pragma once
// Parsing JSON from untrusted files with bounded work: the text's size and nesting depth are
// checked before any parser sees it (nlohmann's dump(), tinygltf's value conversion and other
// tree walks recurse once per level), and a key given twice in one object is an error instead of
// nlohmann's silent "last one wins". Header-only and independent of the rest of Deixis (only
// nlohmann and the standard library), so that the XR test runtime can use it too.
// Errors are JsonGuardError without the file's name: the caller adds it.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace deixis {

// Deixis' own JSON files are 3 to 5 levels deep and a few kilobytes long.
inline constexpr std::size_t kMaxJsonDepth = 64;
inline constexpr std::size_t kMaxJsonFileBytes = std::size_t{16} << 20;

class JsonGuardError : public std::runtime_error {
 public:
  explicit JsonGuardError(const std::string& message) : std::runtime_error(message) {}
};

// Where the text nests arrays and objects deeper than `max_depth` (brackets outside strings
// counted; the text need not be valid JSON), or nothing. Iterative: safe on any input.
inline std::optional<std::string> json_depth_problem(std::string_view text,
                                                     std::size_t max_depth = kMaxJsonDepth) {
  std::size_t depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) {
        return "nested deeper than " + std::to_string(max_depth) + " levels of arrays and " +
               "objects (at byte " + std::to_string(i) + ")";
      }
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::nullopt;
}

namespace json_guard_detail {

// The path of the value being parsed, e.g. "objects[3].name", and the keys seen in every open
// object, kept from nlohmann's parser callback events.
class KeyTracker {
 public:
  using json = nlohmann::json;

  bool on_event(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        open_.push_back({true, {}, {}, 0});
        break;
      case json::parse_event_t::array_start:
        open_.push_back({false, {}, {}, 0});
        break;
      case json::parse_event_t::key: {
        Frame& top = open_.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          throw JsonGuardError("duplicate key '" + top.key + "' in " + path());
        }
        break;
      }
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        open_.pop_back();
        element_done();
        break;
      case json::parse_event_t::value:
        element_done();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object = false;
    std::set<std::string> keys;
    std::string key;        // object: the key whose value is being read
    std::size_t index = 0;  // array: the element being read
  };

  void element_done() {
    if (!open_.empty() && !open_.back().object) {
      ++open_.back().index;
    }
  }

  // The object that holds the duplicate: every open level but the innermost.
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i + 1 < open_.size(); ++i) {
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "[" + to_string(...).
      if (open_[i].object) {
        if (!p.empty()) {
          p.push_back('.');
        }
        p.append(open_[i].key);
      } else {
        p.push_back('[');
        p.append(std::to_string(open_[i].index));
        p.push_back(']');
      }
    }
    return p.empty() ? "the top-level object" : p;
  }

  std::vector<Frame> open_;
};

}  // namespace json_guard_detail

// Parses `text` after the size and depth checks, refusing duplicate keys. Throws JsonGuardError.
inline nlohmann::json parse_guarded_json(std::string_view text) {
  if (text.size() > kMaxJsonFileBytes) {
    throw JsonGuardError(std::to_string(text.size()) + " bytes is more than the " +
                         std::to_string(kMaxJsonFileBytes >> 20) + " MiB a JSON file may have");
  }
  if (const auto problem = json_depth_problem(text)) {
    throw JsonGuardError(*problem);
  }
  json_guard_detail::KeyTracker keys;
  try {
    return nlohmann::json::parse(
        text, [&keys](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
          return keys.on_event(depth, event, parsed);
        });
  } catch (const nlohmann::json::exception& e) {  // syntax errors and number overflows alike
    throw JsonGuardError(std::string("not valid JSON: ") + e.what());
  }
}

// A whole file of at most `max_bytes`, read without trusting its reported size (a pipe or a
// device has none). Throws JsonGuardError.
inline std::string read_bounded_file(const std::filesystem::path& path,
                                     std::size_t max_bytes = kMaxJsonFileBytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw JsonGuardError("cannot open");
  }
  std::string text;
  char chunk[65536];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) {
      throw JsonGuardError("more than the " + std::to_string(max_bytes >> 20) +
                           " MiB a file of this kind may have");
    }
  }
  if (in.bad()) {
    throw JsonGuardError("cannot read");
  }
  return text;
}

}  // namespace deixis
