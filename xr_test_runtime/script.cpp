#include "xr_test_runtime/script.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/io/json_guard.h"

namespace deixis::xrt {

namespace {

using json = nlohmann::json;

struct ParseError {
  std::string what;
};

float number(const json& j, const std::string& where) {
  if (!j.is_number()) {
    throw ParseError{where + ": expected a number"};
  }
  const double v = j.get<double>();
  if (!std::isfinite(v)) {
    throw ParseError{where + ": not finite"};
  }
  return static_cast<float>(v);
}

Eigen::Vector3f vec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) {
    throw ParseError{where + ": expected [x, y, z]"};
  }
  return {number(j[0], where + "[0]"), number(j[1], where + "[1]"), number(j[2], where + "[2]")};
}

ScriptPose pose(const json& j, const std::string& where) {
  if (!j.is_object() || !j.contains("position")) {
    throw ParseError{where + ": expected {\"position\": [x,y,z], \"orientation\": [x,y,z,w]}"};
  }
  ScriptPose p;
  p.position = vec3(j["position"], where + ".position");
  if (j.contains("orientation")) {
    const json& q = j["orientation"];
    if (!q.is_array() || q.size() != 4) {
      throw ParseError{where + ".orientation: expected [x, y, z, w]"};
    }
    Eigen::Quaternionf r(
        number(q[3], where + ".orientation[3]"), number(q[0], where + ".orientation[0]"),
        number(q[1], where + ".orientation[1]"), number(q[2], where + ".orientation[2]"));
    if (std::abs(r.norm() - 1.0f) > 1e-3f) {
      throw ParseError{where + ".orientation: not a unit quaternion"};
    }
    p.orientation = r.normalized();
  }
  return p;
}

ScriptPose lerp(const ScriptPose& a, const ScriptPose& b, float s) {
  return {a.position + s * (b.position - a.position), a.orientation.slerp(s, b.orientation)};
}

float in_range(const json& j, const std::string& where, float lo, float hi) {
  const float v = number(j, where);
  if (v < lo || v > hi) {
    throw ParseError{where + ": must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "]"};
  }
  return v;
}

bool boolean(const json& j, const std::string& where) {
  if (!j.is_boolean()) {
    throw ParseError{where + ": expected true or false"};
  }
  return j.get<bool>();
}

// A control: true/false (a button), a number (an analog value), [x, y] (a stick or trackpad), or
// {"click", "touch", "value", "force", "xy"} for each component on its own.
ScriptControl control(const json& j, const std::string& where) {
  ScriptControl c;
  if (j.is_boolean()) {
    c.click = c.touch = j.get<bool>();
    c.value = c.force = c.click ? 1.0f : 0.0f;
  } else if (j.is_number()) {
    c.value = c.force = in_range(j, where, 0.0f, 1.0f);
    c.touch = c.value > 0.0f;
    c.click = c.value >= 0.5f;
  } else if (j.is_array()) {
    if (j.size() != 2) {
      throw ParseError{where + ": expected [x, y]"};
    }
    c.x = in_range(j[0], where + "[0]", -1.0f, 1.0f);
    c.y = in_range(j[1], where + "[1]", -1.0f, 1.0f);
    c.touch = c.x != 0.0f || c.y != 0.0f;
  } else if (j.is_object()) {
    for (const auto& [field, value] : j.items()) {
      const std::string at = where + "." + field;
      if (field == "click") {
        c.click = boolean(value, at);
      } else if (field == "touch") {
        c.touch = boolean(value, at);
      } else if (field == "value") {
        c.value = in_range(value, at, 0.0f, 1.0f);
      } else if (field == "force") {
        c.force = in_range(value, at, 0.0f, 1.0f);
      } else if (field == "xy") {
        if (!value.is_array()) {
          throw ParseError{at + ": expected [x, y]"};
        }
        const ScriptControl xy = control(value, at);  // nested once at most: an array
        c.x = xy.x;
        c.y = xy.y;
      } else {
        throw ParseError{at + ": unknown component (click, touch, value, force, xy)"};
      }
    }
  } else {
    throw ParseError{where + ": expected true/false, a number, [x, y] or an object"};
  }
  return c;
}

// "input": {"right": {"select": true, "trigger": 0.8, "thumbstick": [0, 1]}, "left": {...}}.
std::vector<ScriptInput> inputs(const json& j, const std::string& where) {
  if (!j.is_object()) {
    throw ParseError{where + ": expected {\"left\": {...}, \"right\": {...}, ...}"};
  }
  std::vector<ScriptInput> out;
  for (const auto& [key, controls] : j.items()) {
    std::optional<TopLevel> top;
    for (std::size_t t = 0; t < kTopLevelCount; ++t) {
      if (top_level_key(static_cast<TopLevel>(t)) == key &&
          t != static_cast<std::size_t>(TopLevel::kEyes)) {
        top = static_cast<TopLevel>(t);
      }
    }
    if (!top) {
      throw ParseError{where + "." + key + ": unknown device (left, right, head, gamepad)"};
    }
    if (!controls.is_object()) {
      throw ParseError{where + "." + key + ": expected {\"identifier\": state, ...}"};
    }
    for (const auto& [identifier, state] : controls.items()) {
      const std::string at = where + "." + key + "." + identifier;
      if (!known_identifier(identifier)) {
        throw ParseError{at + ": no interaction profile has this input"};
      }
      out.push_back({*top, identifier, control(state, at)});
    }
  }
  return out;
}

const ScriptControl* find_control(const ScriptKey& key, TopLevel top, std::string_view identifier) {
  for (const ScriptInput& in : key.inputs) {
    if (in.top == top && in.identifier == identifier) {
      return &in.control;
    }
  }
  return nullptr;
}

XrEnvironmentBlendMode blend_mode(const json& j, const std::string& where) {
  const std::string name = j.is_string() ? j.get<std::string>() : std::string();
  if (name == "OPAQUE") {
    return XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  }
  if (name == "ADDITIVE") {
    return XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
  }
  if (name == "ALPHA_BLEND") {
    return XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND;
  }
  throw ParseError{where + ": expected \"OPAQUE\", \"ADDITIVE\" or \"ALPHA_BLEND\""};
}

// The headset-level fields: blend modes, profiles, captured frames.
void headset(const json& j, Script& s) {
  if (j.contains("blend_modes")) {
    const json& modes = j["blend_modes"];
    if (!modes.is_array() || modes.empty() || modes.size() > 3) {
      throw ParseError{"blend_modes: expected 1 to 3 of \"OPAQUE\", \"ADDITIVE\", \"ALPHA_BLEND\""};
    }
    s.blend_modes.clear();
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const XrEnvironmentBlendMode m =
          blend_mode(modes[i], "blend_modes[" + std::to_string(i) + "]");
      if (std::find(s.blend_modes.begin(), s.blend_modes.end(), m) != s.blend_modes.end()) {
        throw ParseError{"blend_modes[" + std::to_string(i) + "]: listed twice"};
      }
      s.blend_modes.push_back(m);
    }
  }
  if (j.contains("profiles")) {
    const json& list = j["profiles"];
    if (!list.is_array() || list.empty() || list.size() > profiles().size()) {
      throw ParseError{"profiles: expected a non-empty array of interaction profile paths"};
    }
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string where = "profiles[" + std::to_string(i) + "]";
      if (!list[i].is_string() || find_profile(list[i].get<std::string>()) == nullptr) {
        throw ParseError{where +
                         ": not an interaction profile of the spec (e.g. "
                         "\"/interaction_profiles/valve/index_controller\")"};
      }
      s.profiles.push_back(list[i].get<std::string>());
    }
  }
  if (j.contains("capture_frames")) {
    const json& list = j["capture_frames"];
    if (!list.is_array() || list.size() > 64) {
      throw ParseError{"capture_frames: expected an array of at most 64 frame indices"};
    }
    for (std::size_t i = 0; i < list.size(); ++i) {
      if (!list[i].is_number_unsigned() || list[i].get<std::uint64_t>() > (1ull << 40)) {
        throw ParseError{"capture_frames[" + std::to_string(i) +
                         "]: expected an integer from 0 to 2^40"};
      }
      s.capture_frames.push_back(list[i].get<long>());
    }
  }
}

}  // namespace

ScriptControl Script::control_at(double t, TopLevel top, std::string_view identifier) const {
  if (keys.empty()) {
    return {};
  }
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const ScriptKey& k) { return v < k.t; });
  if (next == keys.begin()) {
    const ScriptControl* c = find_control(keys.front(), top, identifier);
    return c != nullptr ? *c : ScriptControl{};
  }
  const ScriptKey& a = *(next - 1);
  const ScriptControl* ca = find_control(a, top, identifier);
  ScriptControl out = ca != nullptr ? *ca : ScriptControl{};
  if (next == keys.end()) {
    return out;
  }
  const ScriptControl* cb = find_control(*next, top, identifier);
  const ScriptControl b = cb != nullptr ? *cb : ScriptControl{};
  const float s = static_cast<float>((t - a.t) / std::max(next->t - a.t, 1e-9));
  out.value += s * (b.value - out.value);
  out.force += s * (b.force - out.force);
  out.x += s * (b.x - out.x);
  out.y += s * (b.y - out.y);
  return out;
}

ScriptSample Script::at(double t) const {
  if (keys.empty()) {
    return {};
  }
  if (t <= keys.front().t) {
    return keys.front().sample;
  }
  if (t >= keys.back().t) {
    return keys.back().sample;
  }
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const ScriptKey& k) { return v < k.t; });
  const ScriptKey& b = *next;
  const ScriptKey& a = *(next - 1);
  const float s = static_cast<float>((t - a.t) / std::max(b.t - a.t, 1e-9));
  ScriptSample out;
  out.head = lerp(a.sample.head, b.sample.head, s);
  const Eigen::Vector3f gaze = a.sample.gaze + s * (b.sample.gaze - a.sample.gaze);
  out.gaze = gaze.norm() > 1e-6f ? gaze.normalized() : a.sample.gaze;
  for (std::size_t h = 0; h < 2; ++h) {
    const ScriptHand& ha = a.sample.hands[h];
    const ScriptHand& hb = b.sample.hands[h];
    out.hands[h].tracked = ha.tracked;  // validity holds until the next key
    if (ha.tracked && hb.tracked) {
      out.hands[h].wrist = lerp(ha.wrist, hb.wrist, s);
      out.hands[h].index_tip = ha.index_tip + s * (hb.index_tip - ha.index_tip);
    } else {
      out.hands[h].wrist = ha.wrist;
      out.hands[h].index_tip = ha.index_tip;
    }
  }
  return out;
}

Script default_script() {
  Script s;
  ScriptKey k;
  k.sample.head.position = Eigen::Vector3f(0.0f, 1.6f, 0.0f);
  for (std::size_t h = 0; h < 2; ++h) {
    const float side = h == 0 ? -1.0f : 1.0f;
    k.sample.hands[h].tracked = true;
    // Hanging arms: fingers down (−Z of the joint along −Y of the stage), backs facing outwards.
    k.sample.hands[h].wrist.position = Eigen::Vector3f(0.2f * side, 0.85f, 0.0f);
    k.sample.hands[h].wrist.orientation =
        Eigen::Quaternionf(Eigen::AngleAxisf(0.5f * 3.14159265f, Eigen::Vector3f::UnitX()));
    k.sample.hands[h].index_tip = Eigen::Vector3f(0.2f * side, 0.68f, 0.0f);
  }
  s.keys.push_back(k);
  return s;
}

std::optional<Script> load_script(const std::string& path, std::string& error) {
  std::string text;
  try {
    text = read_bounded_file(path);
  } catch (const JsonGuardError& e) {
    error = path + ": " + e.what() + " (the script)";
    return std::nullopt;
  }
  try {
    // Bounded depth and no duplicate keys, as every JSON file Deixis reads.
    const json j = parse_guarded_json(text);
    if (!j.is_object()) {
      throw ParseError{"expected a JSON object"};
    }
    Script s;
    if (j.contains("display_hz")) {
      s.display_hz = number(j["display_hz"], "display_hz");
      if (s.display_hz < 1.0 || s.display_hz > 1000.0) {
        throw ParseError{"display_hz: must be in [1, 1000]"};
      }
    }
    if (j.contains("ipd")) {
      s.ipd = number(j["ipd"], "ipd");
    }
    if (j.contains("realtime")) {
      if (!j["realtime"].is_boolean()) {
        throw ParseError{"realtime: expected true or false"};
      }
      s.realtime = j["realtime"].get<bool>();
    }
    for (auto [key, field] :
         {std::pair{"frames", &s.frames}, std::pair{"lose_after_frames", &s.lose_after_frames}}) {
      if (j.contains(key)) {
        // Unsigned first: a value above INT64_MAX would wrap to a negative long.
        if (!j[key].is_number_unsigned() || j[key].get<std::uint64_t>() > (1ull << 40)) {
          throw ParseError{std::string(key) + ": expected an integer from 0 to 2^40"};
        }
        *field = j[key].get<long>();
      }
    }
    headset(j, s);
    if (!j.contains("keys") || !j["keys"].is_array() || j["keys"].empty()) {
      throw ParseError{"keys: expected a non-empty array"};
    }
    const ScriptSample rest = default_script().keys.front().sample;
    for (std::size_t i = 0; i < j["keys"].size(); ++i) {
      const json& jk = j["keys"][i];
      const std::string where = "keys[" + std::to_string(i) + "]";
      ScriptKey k;
      k.sample = rest;
      k.t = number(jk.value("t", json(0.0)), where + ".t");
      if (!s.keys.empty() && k.t <= s.keys.back().t) {
        throw ParseError{where + ".t: keys must be in ascending time"};
      }
      if (jk.contains("head")) {
        k.sample.head = pose(jk["head"], where + ".head");
      }
      k.sample.gaze = (k.sample.head.orientation * Eigen::Vector3f(0, 0, -1)).normalized();
      if (jk.contains("gaze")) {
        const Eigen::Vector3f g = vec3(jk["gaze"], where + ".gaze");
        if (g.norm() < 1e-6f) {
          throw ParseError{where + ".gaze: zero vector"};
        }
        k.sample.gaze = g.normalized();
      }
      for (const char* side : {"left", "right"}) {
        const std::size_t h = side[0] == 'l' ? 0 : 1;
        if (!jk.contains(side)) {
          continue;
        }
        const json& jh = jk[side];
        const std::string hw = where + "." + side;
        if (jh.is_null()) {
          k.sample.hands[h].tracked = false;
          continue;
        }
        k.sample.hands[h].tracked = true;
        k.sample.hands[h].wrist = pose(jh.value("wrist", json()), hw + ".wrist");
        k.sample.hands[h].index_tip = vec3(jh.value("index_tip", json()), hw + ".index_tip");
      }
      if (jk.contains("input")) {
        k.inputs = inputs(jk["input"], where + ".input");
      }
      s.keys.push_back(k);
    }
    return s;
  } catch (const ParseError& e) {
    error = path + ": " + e.what;
  } catch (const JsonGuardError& e) {
    error = path + ": " + e.what();
  } catch (const json::exception& e) {
    error = path + ": " + e.what();
  }
  return std::nullopt;
}

}  // namespace deixis::xrt
