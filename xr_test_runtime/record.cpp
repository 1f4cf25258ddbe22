#include "xr_test_runtime/record.h"

#include <fstream>

#include <nlohmann/json.hpp>

namespace deixis::xrt {

bool Record::write(const std::string& path) const {
  nlohmann::json j;
  j["format"] = "deixis-xr-test-runtime-record";
  j["frames"] = nlohmann::json::array();
  for (const RecordedFrame& f : frames) {
    j["frames"].push_back({{"index", f.index},
                           {"predicted_display_time", f.predicted_display_time},
                           {"submitted_display_time", f.submitted_display_time},
                           {"layers", f.layers},
                           {"projection_views", f.projection_views},
                           {"synced_actions", f.synced_actions}});
  }
  j["refusals"] = nlohmann::json::array();
  for (const RecordedRefusal& r : refusals) {
    j["refusals"].push_back({{"call", r.call}, {"result", r.result}});
  }
  j["states"] = states;
  j["interaction"] = interaction;
  j["gaze_bound"] = gaze_bound;
  std::ofstream out(path);
  out << j.dump(1) << "\n";
  return static_cast<bool>(out);
}

}  // namespace deixis::xrt
