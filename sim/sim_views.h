#pragma once
// The simulator's window layout and its two room views (docs/sim.md): the local room (site A)
// on the left and the remote room (site B) on the right, side by side above the panel. Each
// view renders its room with its own render::Renderer (the room's objects) into an offscreen
// framebuffer the view's size, which is then copied into the window's back buffer, so the
// renderer stays as it is (it draws whole targets) and the panel is drawn over the window after.

#include <optional>
#include <span>

#include "render/offscreen_target.h"
#include "render/renderer.h"
#include "site/site_config.h"
#include "site/site_view.h"

namespace deixis::sim {

// A rectangle of the window in pixels, row 0 at the top (as the mouse reports).
struct ViewRect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
  bool contains(const render::Vec2& p) const;
  // `p` (window pixels) relative to the rectangle's top-left corner.
  render::Vec2 local(const render::Vec2& p) const;
};

struct SimLayout {
  ViewRect local;   // site A: the user's room
  ViewRect remote;  // site B: the avatar's room
  ViewRect panel;   // the ImGui panel below both
};

// The two views share the top of the window; the panel keeps the bottom `panel_fraction`.
SimLayout sim_layout(int width, int height, float panel_fraction = 0.34f);

class RoomView {
 public:
  // Needs the window's GL context current. `map` is the room's objects as first shown.
  RoomView(const site::SiteConfig& site, const TargetMap& map);

  // The window rectangle this view fills (its framebuffer is rebuilt when the size changes).
  void place(const ViewRect& rect);
  const ViewRect& rect() const { return rect_; }
  const render::Camera& camera() const { return camera_; }
  render::Renderer& renderer() { return *renderer_; }

  // The ray from this view's camera through a window pixel.
  render::Ray ray(const render::Vec2& window_pixel) const;

  // Draws `avatars` and `lines` in the room, then copies the picture to its rectangle of the
  // window's back buffer (framebuffer 0, `window_height` pixels tall).
  void draw(std::span<const render::AvatarDraw> avatars, std::span<const render::DebugLine> lines,
            int window_height);

 private:
  site::Camera site_camera_;
  ViewRect rect_;
  render::Camera camera_;
  std::optional<render::Renderer> renderer_;
  std::optional<render::OffscreenTarget> target_;
};

}  // namespace deixis::sim
