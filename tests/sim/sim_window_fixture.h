#pragma once
// What the tests of `deixis sim` as a real process on the network share (sim_network_test,
// sim_room_test): one private X server per test program, the JSON files the runs write, and the
// avatar drawn in room A's view of the last frame's screenshot.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "render/image.h"
#include "render/render_fixtures.h"
#include "render/xvfb_server.h"
#include "sim/sim_views.h"
#include "site/site_config.h"

namespace deixis::sim::testing {

// One private X server for the test program; the simulators it starts inherit its DISPLAY.
inline const render::testing::XvfbServer& display() {
  static render::testing::XvfbServer server;
  return server;
}

inline nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return in ? nlohmann::json::parse(in) : nlohmann::json();
}

// Pixels of the default avatar's dark blue shirt around the chest of whoever stands on avatar
// spot `spot` of `site_file`, in the local view (room A) of the screenshot `shot` of a
// `width` × `height` window (the floor and sky there are a pale grey-blue, blue less than 1.4
// times red). -1 when the chest is not in view.
inline int shirt_on_spot(const std::filesystem::path& site_file, std::size_t spot,
                         const std::filesystem::path& shot, int width, int height) {
  const site::SiteConfig a = site::read_site_config(site_file);
  const SimLayout layout = sim_layout(width, height);
  const render::Camera camera =
      site::site_camera(a.camera, layout.local.width, layout.local.height);
  const Vec3 chest = a.spots.at(spot).floor + Vec3(0, 1.25f, 0);
  const auto at = render::project_to_pixel(camera, layout.local.width, layout.local.height, chest);
  EXPECT_TRUE(at.has_value());
  if (!at) {
    return -1;
  }
  const int x = layout.local.x + static_cast<int>(at->x());
  const int y = layout.local.y + static_cast<int>(at->y());
  EXPECT_TRUE(layout.local.contains(render::Vec2(x, y)));
  const render::Image image = render::read_png(shot);
  EXPECT_EQ(image.width, width);
  const auto shirt = [](const render::testing::Rgb& p) {
    return p[2] > 2 * p[0] && p[2] > p[1] + 20;
  };
  return render::testing::count_pixels(image, {x - 4, y - 4, x + 5, y + 5}, shirt);
}

}  // namespace deixis::sim::testing
