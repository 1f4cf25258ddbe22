// Plays a recorded tracking sequence through a Deixis translator, with the C++ interface
// (deixis/deixis.hpp). The same program as ../c/play_tracking.c, the same output:
//
//   play_tracking_cpp TRACKING.csv TARGET_MAP.json
//
// prints, per tick, the tick, visible, held and the avatar's deictic index fingertip after IK.
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "deixis/deixis.hpp"

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) {
    fields.push_back(field);
  }
  return fields;
}

// The capture CSV's columns by name (docs/dataset.md), read row by row into tracking frames.
class TrackingCsv {
 public:
  explicit TrackingCsv(const std::string& path) : in_(path) {
    std::string line;
    if (!in_ || !std::getline(in_, line)) {
      throw std::runtime_error(path + ": cannot read");
    }
    header_ = split(line);
  }

  std::optional<deixis_tracking_frame> next() {
    std::string line;
    if (!std::getline(in_, line)) {
      return std::nullopt;
    }
    row_ = split(line);
    deixis_tracking_frame f{};
    deixis_tracking_frame_init(&f);
    f.time = value("time");
    f.valid = static_cast<uint32_t>(value("valid"));
    f.head = pose("head");
    f.gaze = vec3("gaze");
    for (int h = 0; h < 2; ++h) {
      const std::string hand = h == DEIXIS_HAND_LEFT ? "left" : "right";
      f.wrist[h] = pose(hand + "_wrist");
      f.index_tip[h] = vec3(hand + "_tip");
    }
    f.head_target = static_cast<int32_t>(value("head_target"));
    f.hand_target = static_cast<int32_t>(value("hand_target"));
    f.head_target_position = vec3("head_target");
    f.hand_target_position = vec3("hand_target");
    return f;
  }

 private:
  double value(const std::string& name) const {
    for (std::size_t i = 0; i < header_.size(); ++i) {
      if (header_[i] == name) {
        return i < row_.size() ? std::strtod(row_[i].c_str(), nullptr) : NAN;
      }
    }
    throw std::runtime_error("no column " + name);
  }
  deixis_vec3 vec3(const std::string& name) const {
    return {static_cast<float>(value(name + "_x")), static_cast<float>(value(name + "_y")),
            static_cast<float>(value(name + "_z"))};
  }
  deixis_pose pose(const std::string& name) const {
    return {vec3(name),
            {static_cast<float>(value(name + "_q_x")), static_cast<float>(value(name + "_q_y")),
             static_cast<float>(value(name + "_q_z")), static_cast<float>(value(name + "_q_w"))}};
  }

  std::ifstream in_;
  std::vector<std::string> header_;
  std::vector<std::string> row_;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: " << argv[0] << " TRACKING.csv TARGET_MAP.json\n";
    return 2;
  }
  try {
    TrackingCsv csv(argv[1]);
    const deixis::lib::Mpnet mpnet;  // the shipped MoE weights
    const deixis::lib::Ugnet ugnet;
    const deixis::lib::Avatar avatar;  // the shipped default avatar
    const deixis::lib::Room room(argv[2]);
    std::optional<deixis::lib::Translator> translator;
    long tick = 0;
    while (const auto frame = csv.next()) {
      if (!translator) {
        deixis_upright_body body{};
        deixis_upright_body_init(&body);
        deixis_translator_config config = deixis::lib::default_translator_config();
        config.person = deixis::lib::calibrate_upright(*frame, body);
        config.avatar_floor.position = {0.3f, 0.0f, -1.0f};
        translator.emplace(mpnet, ugnet, avatar, config);
      }
      const deixis_avatar_frame out = translator->tick(&*frame, room);
      std::printf("%ld %d %d %.5f %.5f %.5f\n", tick++, out.visible, out.held, out.fingertip.x,
                  out.fingertip.y, out.fingertip.z);
    }
  } catch (const std::exception& e) {
    std::cerr << "play_tracking_cpp: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
