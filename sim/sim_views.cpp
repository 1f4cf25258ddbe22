#include "sim/sim_views.h"

#include <algorithm>

namespace deixis::sim {

bool ViewRect::contains(const render::Vec2& p) const {
  return p.x() >= static_cast<float>(x) && p.y() >= static_cast<float>(y) &&
         p.x() < static_cast<float>(x + width) && p.y() < static_cast<float>(y + height);
}

render::Vec2 ViewRect::local(const render::Vec2& p) const {
  return p - render::Vec2(static_cast<float>(x), static_cast<float>(y));
}

SimLayout sim_layout(int width, int height, float panel_fraction) {
  const int panel = std::clamp(static_cast<int>(static_cast<float>(height) * panel_fraction), 0,
                               std::max(height - 2, 0));
  const int view_height = std::max(height - panel, 1);
  const int left = std::max(width / 2, 1);
  return {{0, 0, left, view_height},
          {left, 0, std::max(width - left, 1), view_height},
          {0, view_height, width, panel}};
}

RoomView::RoomView(const site::SiteConfig& site, const TargetMap& map) : site_camera_(site.camera) {
  renderer_.emplace();
  renderer_->set_targets(map);
}

void RoomView::place(const ViewRect& rect) {
  const bool resized = rect.width != rect_.width || rect.height != rect_.height;
  rect_ = rect;
  if (resized || !target_) {
    target_.emplace(rect.width, rect.height);
    camera_ = site::site_camera(site_camera_, rect.width, rect.height);
  }
}

render::Ray RoomView::ray(const render::Vec2& window_pixel) const {
  return render::pixel_ray(camera_, rect_.width, rect_.height, rect_.local(window_pixel));
}

void RoomView::draw(std::span<const render::AvatarDraw> avatars,
                    std::span<const render::DebugLine> lines, int window_height) {
  render::SceneView view;
  view.camera = camera_;
  view.avatars = avatars;
  view.lines = lines;
  const render::RenderTarget target = target_->target();
  renderer_->render(view, target);
  // OpenGL's rows count from the bottom: the rectangle's top row is window_height − y.
  const int top = window_height - rect_.y;
  glBlitNamedFramebuffer(target.framebuffer, 0, 0, 0, target.width, target.height, rect_.x,
                         top - rect_.height, rect_.x + rect_.width, top, GL_COLOR_BUFFER_BIT,
                         GL_NEAREST);
  // The renderer left its own framebuffer bound; whatever draws next (the panel) draws into the
  // window.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace deixis::sim
