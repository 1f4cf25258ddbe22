#include "xr_test_runtime/record.h"

#include <fstream>

#include <nlohmann/json.hpp>

namespace deixis::xrt {

bool Record::write(const std::string& path) const {
  nlohmann::json j;
  j["format"] = "deixis-xr-test-runtime-record";
  j["frames"] = nlohmann::json::array();
  for (const RecordedFrame& f : frames) {
    nlohmann::json layers = nlohmann::json::array();
    for (const RecordedLayer& l : f.layer_list) {
      nlohmann::json images = nlohmann::json::array();
      for (const RecordedImage& i : l.images) {
        images.push_back({{"file", i.file},
                          {"width", i.width},
                          {"height", i.height},
                          {"transparent", i.transparent},
                          {"opaque", i.opaque},
                          {"partial", i.partial}});
      }
      layers.push_back({{"type", l.type}, {"flags", l.flags}, {"views", l.views}});
      if (!images.empty()) {
        layers.back()["images"] = images;
      }
    }
    j["frames"].push_back({{"index", f.index},
                           {"predicted_display_time", f.predicted_display_time},
                           {"submitted_display_time", f.submitted_display_time},
                           {"layers", f.layers},
                           {"projection_views", f.projection_views},
                           {"synced_actions", f.synced_actions},
                           {"blend_mode", f.blend_mode},
                           {"layer_list", layers}});
  }
  j["refusals"] = nlohmann::json::array();
  for (const RecordedRefusal& r : refusals) {
    j["refusals"].push_back({{"call", r.call}, {"result", r.result}});
  }
  j["states"] = states;
  j["interaction"] = interaction;
  j["gaze_bound"] = gaze_bound;
  j["graphics"] = graphics;
  j["profiles"] = nlohmann::json::object();
  for (const auto& [top, profile] : profiles) {
    j["profiles"][top] = profile;
  }
  j["ignored_bindings"] = nlohmann::json::array();
  for (const RecordedIgnoredBinding& b : ignored_bindings) {
    j["ignored_bindings"].push_back({{"action", b.action}, {"path", b.path}});
  }
  j["haptics"] = nlohmann::json::array();
  for (const RecordedHaptic& h : haptics) {
    nlohmann::json e = {
        {"time", h.time}, {"action", h.action}, {"subaction", h.subaction}, {"outputs", h.outputs}};
    if (h.stop) {
      e["stop"] = true;
    } else {
      e["duration"] = h.duration;
      e["frequency"] = h.frequency;
      e["amplitude"] = h.amplitude;
    }
    j["haptics"].push_back(e);
  }
  j["haptics_dropped"] = haptics_dropped;
  std::ofstream out(path);
  out << j.dump(1) << "\n";
  return static_cast<bool>(out);
}

}  // namespace deixis::xrt
