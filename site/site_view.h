#pragma once
// A site's headless picture (render/): two views of this room from the site's camera, side by
// side in one frame: on the left its own user (an avatar copying their pose where they stand), on
// the right the remote people's avatars as translated into this room. Frames go to a video (one
// per site; the demo puts the sites' halves together) and the last one can be saved as a PNG.
//
// Rendering needs an EGL surfaceless context (Mesa; llvmpipe without a GPU). draw() allocates
// nothing once the first frame is drawn.

#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "avatar/avatar_loader.h"
#include "render/headless_context.h"
#include "render/image.h"
#include "render/mesh_cache.h"
#include "render/renderer.h"
#include "render/video_writer.h"
#include "site/site_config.h"

namespace deixis::site {

// One avatar as drawn: where its model frame is and its joints' model poses; a ray from its eyes
// through its fingertip toward what it designates, when it does. `mesh`: what it wears, null for
// the site's own avatar (a remote person's chosen one, site/remote_people.h: one pose per joint
// of its rig).
struct AvatarPicture {
  Pose T_world_model;
  std::span<const Pose> T_model_joint;
  bool show_ray = false;
  Vec3 ray_from = Vec3::Zero();
  Vec3 ray_to = Vec3::Zero();
  const avatar::SkinnedMesh* mesh = nullptr;
  float opacity = 1.0f;  // below 1: fading in or out (site/remote_people.h)
};

// The camera a site's configuration frames its room with, for an image of width × height.
render::Camera site_camera(const Camera& camera, int width, int height);

class SiteView {
 public:
  // `view_width` × `view_height` per view (even numbers); `video`: the .mp4 to write, or empty.
  // Throws deixis::Error when EGL, the renderer or ffmpeg cannot start.
  SiteView(const SiteConfig& site, const avatar::Avatar& avatar, int view_width, int view_height,
           const std::filesystem::path& video);
  ~SiteView();
  SiteView(const SiteView&) = delete;
  SiteView& operator=(const SiteView&) = delete;

  // Draws both views (`remote` null: the avatar is hidden) and appends the frame to the video.
  void draw(const AvatarPicture& user, const AvatarPicture* remote);
  // The same with every visible remote person's avatar in the right view (a room of several
  // people, site/remote_people.h); at most one per spot of the site. A picture's mesh is
  // uploaded the first time it is drawn (then kept by address: it must not be freed and another
  // made in its place while the view lives; at most kMaxMeshes, beyond which such pictures are
  // not drawn).
  void draw(const AvatarPicture& user, std::span<const AvatarPicture> remote);
  const render::Image& frame() const { return frame_; }
  // Finishes the video; throws deixis::Error if ffmpeg failed.
  void finish();

  static constexpr std::size_t kMaxMeshes = render::SkinnedMeshCache::kMaxMeshes;
  std::size_t meshes() const { return meshes_->size(); }  // uploaded, the site's own included

 private:
  void draw_view(std::span<const AvatarPicture> pictures, int column);

  int view_width_;
  int view_height_;
  render::Camera camera_;
  render::HeadlessContext context_;
  std::optional<render::Renderer> renderer_;
  std::optional<render::SkinnedMeshCache> meshes_;
  std::vector<render::AvatarDraw> avatars_;  // sized at construction: one per spot
  std::vector<render::DebugLine> lines_;
  render::Image view_;   // one view, read back
  render::Image frame_;  // both views side by side
  std::unique_ptr<render::VideoWriter> video_;
};

}  // namespace deixis::site
