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

}  // namespace

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
