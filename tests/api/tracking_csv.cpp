#include "api/tracking_csv.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "avatar/avatar_loader.h"
#include "gesture/upright_calibration.h"
#include "presence/remote_avatar.h"
#include "test_support.h"

namespace deixis::testing {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  for (std::string field; std::getline(in, field, ',');) {
    fields.push_back(field);
  }
  return fields;
}

struct Row {
  const std::vector<std::string>& header;
  const std::vector<std::string>& fields;

  double value(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name && i < fields.size()) {
        return std::stod(fields[i]);
      }
    }
    throw std::runtime_error("tracking CSV: no column " + name);
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
};

Vec3 v(const deixis_vec3& c) {
  return {c.x, c.y, c.z};
}

Pose pose(const deixis_pose& c) {
  const Quat q(c.orientation.w, c.orientation.x, c.orientation.y, c.orientation.z);
  return {Quat(q.coeffs() / q.norm()).toRotationMatrix(), v(c.position)};
}

}  // namespace

std::filesystem::path examples_dir() {
  return source_dir() / "examples";
}

std::vector<deixis_tracking_frame> read_tracking_csv(const std::filesystem::path& csv) {
  std::ifstream in(csv);
  std::string line;
  if (!std::getline(in, line)) {
    throw std::runtime_error(csv.string() + ": cannot read");
  }
  const std::vector<std::string> header = split(line);
  std::vector<deixis_tracking_frame> frames;
  while (std::getline(in, line)) {
    const std::vector<std::string> fields = split(line);
    const Row row{header, fields};
    deixis_tracking_frame f{};
    f.time = row.value("time");
    f.valid = static_cast<std::uint32_t>(row.value("valid"));
    f.head = row.pose("head");
    f.gaze = row.vec3("gaze");
    for (int h = 0; h < 2; ++h) {
      const std::string hand = h == 0 ? "left" : "right";
      f.wrist[h] = row.pose(hand + "_wrist");
      f.index_tip[h] = row.vec3(hand + "_tip");
    }
    f.head_target = static_cast<std::int32_t>(row.value("head_target"));
    f.hand_target = static_cast<std::int32_t>(row.value("hand_target"));
    f.head_target_position = row.vec3("head_target");
    f.hand_target_position = row.vec3("hand_target");
    frames.push_back(f);
  }
  return frames;
}

TrackingFrame runtime_frame(const deixis_tracking_frame& c) {
  TrackingFrame f;
  f.time = c.time;
  f.T_world_head = pose(c.head);
  f.gaze = v(c.gaze);
  for (int h = 0; h < 2; ++h) {
    f.T_world_wrist[h] = pose(c.wrist[h]);
    f.index_tip[h] = v(c.index_tip[h]);
  }
  f.valid = static_cast<std::uint8_t>(c.valid);
  f.head_target = c.head_target;
  f.hand_target = c.hand_target;
  f.head_target_position = v(c.head_target_position);
  f.hand_target_position = v(c.hand_target_position);
  return f;
}

std::vector<std::string> in_tree_fingertips(const std::filesystem::path& csv,
                                            const std::filesystem::path& target_map) {
  const std::filesystem::path assets = source_dir() / "assets";
  const ik::AvatarSolver solver =
      ik::AvatarSolver::build(avatar::load_avatar(assets / "avatars/default.glb").rig);
  const TargetMap room = read_target_map(target_map);
  const LocalTargets targets{&room, Vec3::Zero()};
  std::vector<std::string> lines;
  std::unique_ptr<presence::RemoteAvatar> avatar;
  long tick = 0;
  for (const deixis_tracking_frame& c : read_tracking_csv(csv)) {
    const TrackingFrame frame = runtime_frame(c);
    if (!avatar) {
      presence::RemoteAvatarConfig config;
      config.user = calibrate_upright(frame, UprightBody{});
      config.T_world_floor.translation = Vec3(0.3f, 0.0f, -1.0f);
      const std::filesystem::path w = assets / "weights/right";
      avatar = std::make_unique<presence::RemoteAvatar>(
          nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors"),
          nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors"), solver, config);
    }
    avatar->tick(&frame, targets);
    const Vec3 tip = avatar->index_fingertip();
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "%ld %d %d %.5f %.5f %.5f", tick++,
                  avatar->visible() ? 1 : 0, avatar->frame().held ? 1 : 0,
                  static_cast<double>(tip.x()), static_cast<double>(tip.y()),
                  static_cast<double>(tip.z()));
    lines.emplace_back(buffer);
  }
  return lines;
}

std::vector<PrintedTick> parse_ticks(const std::vector<std::string>& lines) {
  std::vector<PrintedTick> ticks;
  for (const std::string& line : lines) {
    PrintedTick t;
    float x = 0, y = 0, z = 0;
    if (std::sscanf(line.c_str(), "%ld %d %d %f %f %f", &t.tick, &t.visible, &t.held, &x, &y, &z) ==
        6) {
      t.fingertip = Vec3(x, y, z);
      ticks.push_back(t);
    }
  }
  return ticks;
}

}  // namespace deixis::testing
