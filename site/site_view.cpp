#include "site/site_view.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <numbers>

namespace deixis::site {

render::Camera site_camera(const Camera& c, int width, int height) {
  const float vertical = c.fov_degrees * std::numbers::pi_v<float> / 180.0f;
  return render::look_at(
      c.position, c.look_at,
      render::symmetric_fov(vertical, static_cast<float>(width) / static_cast<float>(height)));
}

SiteView::SiteView(const SiteConfig& site, const avatar::Avatar& avatar, int view_width,
                   int view_height, const std::filesystem::path& video)
    : view_width_(view_width),
      view_height_(view_height),
      camera_(site_camera(site.camera, view_width, view_height)),
      context_(view_width, view_height) {
  renderer_.emplace();
  renderer_->set_targets(site.target_map);
  // The user's copy and remote people wear the site's avatar (the site file names one) unless a
  // person wears their own; one uploaded mesh serves them all.
  meshes_.emplace(*renderer_, avatar.mesh);
  avatars_.reserve(std::max<std::size_t>(site.spots.size(), 1));
  lines_.reserve(avatars_.capacity());
  frame_.width = 2 * view_width;
  frame_.height = view_height;
  frame_.rgb.assign(static_cast<std::size_t>(frame_.width) * view_height * 3, 0);
  if (!video.empty()) {
    render::VideoOptions options;
    options.width = frame_.width;
    options.height = frame_.height;
    options.frames_per_second = 30;
    options.crf = 23;
    video_ = std::make_unique<render::VideoWriter>(video, options);
  }
}

SiteView::~SiteView() {
  video_.reset();  // ffmpeg finishes (errors only logged) before the GL objects go
  renderer_.reset();
}

void SiteView::draw(const AvatarPicture& user, const AvatarPicture* remote) {
  draw(user, remote != nullptr ? std::span<const AvatarPicture>(remote, 1)
                               : std::span<const AvatarPicture>());
}

void SiteView::draw(const AvatarPicture& user, std::span<const AvatarPicture> remote) {
  draw_view({&user, 1}, 0);
  draw_view(remote, 1);
  if (video_) {
    video_->write(frame_);
  }
}

void SiteView::draw_view(std::span<const AvatarPicture> pictures, int column) {
  avatars_.clear();
  lines_.clear();
  for (const AvatarPicture& picture : pictures) {
    if (avatars_.size() == avatars_.capacity()) {
      break;  // more than the site has spots for: never, as people take spots
    }
    const std::optional<render::SkinnedMeshId> mesh = meshes_->get(picture.mesh);
    if (!mesh) {
      continue;
    }
    avatars_.push_back({*mesh, picture.T_world_model, picture.T_model_joint, picture.opacity});
    if (picture.show_ray) {
      render::DebugLine& line = lines_.emplace_back();
      line.from = picture.ray_from;
      line.to = picture.ray_to;
    }
  }
  render::SceneView view;
  view.camera = camera_;
  view.avatars = avatars_;
  view.lines = lines_;
  const render::RenderTarget target = context_.target();
  renderer_->render(view, target);
  context_.present();
  render::read_pixels(target, view_);
  // Into its half of the frame, row by row.
  const std::size_t row = static_cast<std::size_t>(view_width_) * 3;
  for (int y = 0; y < view_height_; ++y) {
    std::memcpy(frame_.rgb.data() + (static_cast<std::size_t>(y) * 2 + column) * row,
                view_.rgb.data() + static_cast<std::size_t>(y) * row, row);
  }
}

void SiteView::finish() {
  if (video_) {
    video_->finish();
  }
}

}  // namespace deixis::site
