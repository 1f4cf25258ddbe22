// Headless renders of known scenes (EGL surfaceless, llvmpipe) checked by where pixels are and
// what colour they have: the skinned arm's silhouette, its pointing side, a bent elbow, the
// avatar's placement in the room, target objects in their colours, labels, floor and debug lines.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "render/headless_context.h"
#include "render/mesh_cache.h"
#include "render/renderer.h"
#include "render_fixtures.h"

namespace deixis::render {
namespace {

using namespace deixis::render::testing;

class HeadlessRenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context_.emplace(kWidth, kHeight);
    renderer_.emplace();
    skeleton_ = arm_skeleton();
    arm_ = renderer_->add_skinned_mesh(arm_mesh(skeleton_));
  }
  void TearDown() override {
    renderer_.reset();  // GL objects go while the context is current
    context_.reset();
  }

  // Renders the arm in `pose` (and whatever else `view` holds) without floor or targets unless
  // asked for.
  Image render_arm(const std::vector<Pose>& pose, SceneView view = bare_view(),
                   const Pose& T_world_model = Pose{}) {
    const AvatarDraw avatar{arm_, T_world_model, pose};
    view.avatars = {&avatar, 1};
    renderer_->render(view, context_->target());
    context_->present();
    check_gl("render");
    return read_pixels(context_->target());
  }

  static SceneView bare_view() {
    SceneView view;
    view.camera = front_camera();
    view.show_floor = false;
    view.show_targets = false;
    return view;
  }

  bool is_background(const Rgb& p) const {
    return near(p, to_rgb(renderer_->options().background), 2);
  }
  bool is_foreground(const Rgb& p) const { return !is_background(p); }

  int foreground_in(const Image& image, Region r) const {
    return count_pixels(image, r, [this](const Rgb& p) { return is_foreground(p); });
  }

  std::optional<HeadlessContext> context_;
  std::optional<Renderer> renderer_;
  ik::Skeleton skeleton_;
  SkinnedMeshId arm_;
};

TEST_F(HeadlessRenderTest, ArmSilhouetteIsWhereTheBonesAre) {
  const Camera camera = front_camera();
  const Image image = render_arm(arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity()));
  // Along both bones: arm. A tube radius and more above and below them, and on the other side of
  // the shoulder: background.
  for (float x = 0.05f; x < kUpperArm + kForearm - 0.02f; x += 0.05f) {
    SCOPED_TRACE(x);
    EXPECT_TRUE(is_foreground(pixel_at(image, camera, kShoulder + Vec3(x, 0, 0))));
    EXPECT_TRUE(is_background(pixel_at(image, camera, kShoulder + Vec3(x, 0.15f, 0))));
    EXPECT_TRUE(is_background(pixel_at(image, camera, kShoulder + Vec3(x, -0.15f, 0))));
    EXPECT_TRUE(is_background(pixel_at(image, camera, kShoulder + Vec3(-x - 0.1f, 0, 0))));
  }
  // The silhouette's area is the projected tube's (0.65 m × 0.12 m at 2.5 m), within a margin.
  const float pixels_per_metre = kHeight / (2.0f * 2.5f * std::tan(0.5f * 1.0471976f));
  const float expected =
      (kUpperArm + kForearm) * 2 * kArmRadius * pixels_per_metre * pixels_per_metre;
  const int area = foreground_in(image, whole(image));
  EXPECT_GT(area, 0.7f * expected);
  EXPECT_LT(area, 1.4f * expected);
}

TEST_F(HeadlessRenderTest, ArmPointingRightOrLeftPutsItsPixelsOnThatSide) {
  const Region left{0, 0, kWidth / 2 - 4, kHeight};
  const Region right{kWidth / 2 + 4, 0, kWidth, kHeight};
  const Image pointing_right = render_arm(arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity()));
  // Half a turn about +Y at the shoulder: the arm points along −X, the viewer's left.
  const Image pointing_left =
      render_arm(arm_pose(skeleton_, about_y(3.14159265f), Mat3::Identity()));
  EXPECT_GT(foreground_in(pointing_right, right), 300);
  EXPECT_EQ(foreground_in(pointing_right, left), 0);
  EXPECT_GT(foreground_in(pointing_left, left), 300);
  EXPECT_EQ(foreground_in(pointing_left, right), 0);
}

TEST_F(HeadlessRenderTest, BentElbowMovesTheForearmOnly) {
  const Camera camera = front_camera();
  // +90° about +Z at the elbow: the forearm points up.
  const Image image = render_arm(arm_pose(skeleton_, Mat3::Identity(), about_z(1.5707963f)));
  const Vec3 elbow = kShoulder + Vec3(kUpperArm, 0, 0);
  EXPECT_TRUE(is_foreground(pixel_at(image, camera, kShoulder + Vec3(0.15f, 0, 0))));  // upper arm
  EXPECT_TRUE(is_foreground(pixel_at(image, camera, elbow + Vec3(0, 0.15f, 0))));      // forearm
  EXPECT_TRUE(is_foreground(pixel_at(image, camera, elbow + Vec3(0, 0.25f, 0))));
  EXPECT_TRUE(is_background(pixel_at(image, camera, elbow + Vec3(0.2f, 0, 0))));  // where it was
}

TEST_F(HeadlessRenderTest, AllFourInfluenceSlotsAreSkinned) {
  // The same arm with every vertex's influences stored in reverse slot order: a shader that read
  // only some of the four slots would lose (or collapse) vertices.
  SkinnedMesh reversed = arm_mesh(skeleton_);
  for (std::size_t v = 0; v < reversed.joints.size(); ++v) {
    std::reverse(reversed.joints[v].begin(), reversed.joints[v].end());
    std::reverse(reversed.weights[v].begin(), reversed.weights[v].end());
  }
  const SkinnedMeshId reversed_id = renderer_->add_skinned_mesh(reversed);
  const std::vector<Pose> bent = arm_pose(skeleton_, about_y(0.4f), about_z(1.2f));
  const Image original = render_arm(bent);
  const SkinnedMeshId original_id = arm_;
  arm_ = reversed_id;
  const Image swapped = render_arm(bent);
  arm_ = original_id;
  int different = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      different += near(original.pixel(x, y), swapped.pixel(x, y), 3) ? 0 : 1;
    }
  }
  EXPECT_GT(foreground_in(original, whole(original)), 300);
  EXPECT_LE(different, 5);
}

TEST_F(HeadlessRenderTest, AvatarIsPlacedByItsModelPose) {
  const Camera camera = front_camera();
  const Pose T_world_model{Mat3::Identity(), Vec3(-0.9f, 0.3f, 0.0f)};
  const Image image = render_arm(arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity()),
                                 bare_view(), T_world_model);
  EXPECT_TRUE(is_foreground(
      pixel_at(image, camera, T_world_model.translation + kShoulder + Vec3(0.3f, 0, 0))));
  EXPECT_TRUE(is_background(pixel_at(image, camera, kShoulder + Vec3(0.3f, 0, 0))));
}

TEST_F(HeadlessRenderTest, TargetsAreDrawnInTheirColoursWherePlaced) {
  TargetMap room;
  room.objects = {
      {1, "Jupiter", TargetKind::kSphere, Vec3(-0.9f, 1.2f, 0), Vec3::Constant(0.4f)},
      {2, "Box", TargetKind::kBox, Vec3(0.9f, 0.9f, 0), Vec3::Constant(0.3f)},
      {3, "TV", TargetKind::kScreen, Vec3(0.0f, 1.85f, -0.5f), Vec3(0.8f, 0.45f, 0.05f)}};
  renderer_->set_targets(room);
  SceneView view = bare_view();
  view.show_targets = true;
  view.show_labels = false;
  renderer_->render(view, context_->target());
  const Image image = read_pixels(context_->target());
  const Camera& camera = view.camera;
  for (const TargetObject& object : room.objects) {
    SCOPED_TRACE(object.name);
    const Rgb centre = pixel_at(image, camera, object.position);
    EXPECT_TRUE(same_hue(centre, target_colour(object.id)))
        << int{centre[0]} << " " << int{centre[1]} << " " << int{centre[2]};
    // Just beside the object: background.
    const Vec3 beside = object.position + Vec3(0.5f * object.size.x() + 0.08f, 0, 0);
    EXPECT_TRUE(is_background(pixel_at(image, camera, beside)));
  }
  // Distinct colours: the sphere's pixel is not the box's hue.
  EXPECT_FALSE(same_hue(pixel_at(image, camera, room.objects[0].position), target_colour(2)));
}

TEST_F(HeadlessRenderTest, AMovedTargetIsDrawnAtItsNewPlaceOnly) {
  TargetMap room;
  room.objects = {{1, "Jupiter", TargetKind::kSphere, Vec3(-0.9f, 1.2f, 0), Vec3::Constant(0.4f)}};
  renderer_->set_targets(room);
  const Vec3 moved(0.8f, 1.0f, 0.0f);
  EXPECT_TRUE(renderer_->move_target(1, moved));
  EXPECT_FALSE(renderer_->move_target(7, moved));  // no such object
  SceneView view = bare_view();
  view.show_targets = true;
  view.show_labels = false;
  renderer_->render(view, context_->target());
  const Image image = read_pixels(context_->target());
  EXPECT_TRUE(same_hue(pixel_at(image, view.camera, moved), target_colour(1)));
  EXPECT_TRUE(is_background(pixel_at(image, view.camera, room.objects[0].position)));
}

TEST_F(HeadlessRenderTest, LabelsAreDrawnAboveTheirObjects) {
  RendererOptions options;
  options.label_height = 0.25f;  // legible at 320 × 240 from 2.5 m
  renderer_.emplace(options);
  TargetMap room;
  room.objects = {{1, "Jupiter", TargetKind::kSphere, Vec3(-0.5f, 1.0f, 0), Vec3::Constant(0.3f)}};
  renderer_->set_targets(room);
  SceneView view = bare_view();
  view.show_targets = true;
  const auto is_text = [&](const Rgb& p) { return near(p, to_rgb(options.label_text), 8); };

  renderer_->render(view, context_->target());
  const Image labelled = read_pixels(context_->target());
  view.show_labels = false;
  renderer_->render(view, context_->target());
  const Image unlabelled = read_pixels(context_->target());

  const Camera& camera = view.camera;
  const Vec2 top = *project_to_pixel(camera, kWidth, kHeight, Vec3(-0.5f, 1.15f, 0));
  const Vec2 centre = *project_to_pixel(camera, kWidth, kHeight, Vec3(-0.5f, 1.0f, 0));
  const float pixels_per_metre = (centre.y() - top.y()) / 0.15f;
  const int plate = static_cast<int>(options.label_height * pixels_per_metre);
  const int gap = static_cast<int>(options.label_gap * pixels_per_metre);
  const Region above{static_cast<int>(top.x()) - 3 * plate,
                     static_cast<int>(top.y()) - gap - plate - 3,
                     static_cast<int>(top.x()) + 3 * plate, static_cast<int>(top.y())};
  EXPECT_GT(count_pixels(labelled, above, is_text), 40);
  EXPECT_EQ(count_pixels(unlabelled, whole(unlabelled), is_text), 0);
  // The text is nowhere but above its object.
  EXPECT_EQ(count_pixels(labelled, whole(labelled), is_text),
            count_pixels(labelled, above, is_text));
}

// A remote person's avatar fading in or out (site/remote_people.h) is blended over what is
// behind it by its opacity: half-way, each pixel is half the opaque avatar's and half the
// background's; at 0 nothing is drawn.
TEST_F(HeadlessRenderTest, AFadingAvatarIsBlendedOverWhatIsBehindIt) {
  const std::vector<Pose> pose = arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity());
  const auto render_at = [&](float opacity) {
    const AvatarDraw avatar{arm_, Pose{}, pose, opacity};
    SceneView view = bare_view();
    view.avatars = {&avatar, 1};
    renderer_->render(view, context_->target());
    return read_pixels(context_->target());
  };
  const Image opaque = render_at(1.0f);
  const Image half = render_at(0.5f);
  const Image gone = render_at(0.0f);
  const Rgb background = to_rgb(renderer_->options().background);
  int blended = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const Rgb o = opaque.pixel(x, y);
      const Rgb h = half.pixel(x, y);
      ASSERT_TRUE(near(gone.pixel(x, y), background, 1)) << x << "," << y;
      if (near(o, background, 2)) {
        ASSERT_TRUE(near(h, background, 2)) << x << "," << y;
        continue;
      }
      const Rgb expected{static_cast<std::uint8_t>((o[0] + background[0] + 1) / 2),
                         static_cast<std::uint8_t>((o[1] + background[1] + 1) / 2),
                         static_cast<std::uint8_t>((o[2] + background[2] + 1) / 2)};
      blended += near(h, expected, 3) ? 1 : 0;
    }
  }
  const int area = foreground_in(opaque, whole(opaque));
  ASSERT_GT(area, 400);
  EXPECT_GT(blended, area * 95 / 100) << "of " << area << " avatar pixels";
}

// Over a see-through headset's transparent background the blended avatar carries its opacity as
// alpha, with premultiplied colour (what ALPHA_BLEND composites, xr/blend_mode.h).
TEST_F(HeadlessRenderTest, AFadingAvatarOverTransparentBlackCarriesItsOpacityAsAlpha) {
  renderer_.emplace(RendererOptions{.background = Colour(0, 0, 0, 0)});
  arm_ = renderer_->add_skinned_mesh(arm_mesh(skeleton_));
  const std::vector<Pose> pose = arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity());
  const AvatarDraw avatar{arm_, Pose{}, pose, 0.4f};
  SceneView view = bare_view();
  view.avatars = {&avatar, 1};
  renderer_->render(view, context_->target());
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(kWidth) * kHeight * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, context_->target().framebuffer);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, kWidth, kHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  int covered = 0;
  for (std::size_t i = 0; i < rgba.size(); i += 4) {
    const int alpha = rgba[i + 3];
    if (alpha == 0) {
      EXPECT_EQ(rgba[i] + rgba[i + 1] + rgba[i + 2], 0);
      continue;
    }
    ++covered;
    EXPECT_NEAR(alpha, 102, 2);  // 0.4 × 255
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(rgba[i + static_cast<std::size_t>(k)], alpha + 1) << "premultiplied";
    }
  }
  EXPECT_GT(covered, 400) << covered;
}

// The head-locked panel (render/scene.h, HeadPanel): its lines are drawn over everything where
// it is placed (here 0.6 m ahead of the camera, in front of the arm), left-aligned on dark
// plates, and nothing of it elsewhere; other text redraws it.
TEST_F(HeadlessRenderTest, TheHeadPanelIsDrawnOverEverythingWherePlaced) {
  const Camera camera = front_camera();
  const std::vector<Pose> pose = arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity());
  const AvatarDraw avatar{arm_, Pose{}, pose};
  SceneView view = bare_view();
  view.avatars = {&avatar, 1};
  const std::string_view long_lines[] = {"Deixis: connected, 1 person here",
                                         "B: live, rtt 3 ms, buffer 50 ms, dropped 0 of 150"};
  HeadPanel panel;
  panel.T_world_panel = compose(camera.T_world_eye, Pose{Mat3::Identity(), Vec3(0, 0, -0.6f)});
  panel.lines = long_lines;
  panel.line_height = 0.03f;
  view.panel = &panel;
  const RendererOptions& options = renderer_->options();
  const auto is_text = [&](const Rgb& p) { return near(p, to_rgb(options.label_text), 8); };
  const auto is_plate = [&](const Rgb& p) {
    // The backing colour at its alpha over the background.
    const Colour b = options.label_backing;
    const Colour bg = options.background;
    const Colour over = b * b.w() + bg * (1.0f - b.w());
    return near(p, to_rgb(over), 6);
  };
  renderer_->render(view, context_->target());
  const Image with_panel = read_pixels(context_->target());
  // Two lines 0.03 m each at 0.6 m: about 30 px tall around the centre.
  const Vec2 centre = *project_to_pixel(camera, kWidth, kHeight, panel.T_world_panel.translation);
  const Region around{static_cast<int>(centre.x()) - kWidth / 2, static_cast<int>(centre.y()) - 20,
                      static_cast<int>(centre.x()) + kWidth / 2, static_cast<int>(centre.y()) + 20};
  EXPECT_GT(count_pixels(with_panel, around, is_text), 150);
  EXPECT_GT(count_pixels(with_panel, around, is_plate), 1000);
  EXPECT_EQ(count_pixels(with_panel, whole(with_panel), is_text),
            count_pixels(with_panel, around, is_text))
      << "text only where the panel is";
  // Over the arm, which is nearer nothing than the panel is: the arm's pixel behind the panel
  // is darkened by the plate (or is text), not the arm's own.
  const Vec3 on_arm = kShoulder + Vec3(0.05f, 0, 0);
  view.panel = nullptr;
  renderer_->render(view, context_->target());
  const Rgb arm_alone = pixel_at(read_pixels(context_->target()), camera, on_arm);
  view.panel = &panel;
  const Rgb arm_under = pixel_at(with_panel, camera, on_arm);
  const auto sum = [](const Rgb& p) { return int{p[0]} + int{p[1]} + int{p[2]}; };
  EXPECT_TRUE(is_text(arm_under) || sum(arm_under) < sum(arm_alone) / 2)
      << sum(arm_under) << " vs " << sum(arm_alone);

  // Left-aligned: both lines start at the same column, the shorter ends sooner.
  const auto first_column = [&](const Image& image, int y0, int y1) {
    for (int x = 0; x < kWidth; ++x) {
      if (count_pixels(image, Region{x, y0, x + 1, y1}, is_plate) > 0) {
        return x;
      }
    }
    return -1;
  };
  const int cy = static_cast<int>(centre.y());
  const int top_start = first_column(with_panel, cy - 14, cy - 2);
  const int bottom_start = first_column(with_panel, cy + 2, cy + 14);
  ASSERT_GE(top_start, 0);
  EXPECT_NEAR(top_start, bottom_start, 1);

  // Other text: redrawn (one short line has far less text), and none without a panel.
  const std::string_view short_line[] = {"ok"};
  panel.lines = short_line;
  renderer_->render(view, context_->target());
  const Image short_panel = read_pixels(context_->target());
  EXPECT_LT(count_pixels(short_panel, whole(short_panel), is_text),
            count_pixels(with_panel, whole(with_panel), is_text) / 5);
  EXPECT_GT(count_pixels(short_panel, whole(short_panel), is_text), 5);
  view.panel = nullptr;
  renderer_->render(view, context_->target());
  const Image no_panel = read_pixels(context_->target());
  EXPECT_EQ(count_pixels(no_panel, whole(no_panel), is_text), 0);
  EXPECT_EQ(count_pixels(no_panel, whole(no_panel), is_plate), 0);
}

TEST_F(HeadlessRenderTest, FloorFillsTheLowerHalfOnly) {
  SceneView view = bare_view();
  view.show_floor = true;
  renderer_->render(view, context_->target());
  const Image image = read_pixels(context_->target());
  const Region bottom{0, kHeight - 20, kWidth, kHeight};
  const Region top{0, 0, kWidth, 20};
  // Row 0 of the image is the top: the floor is below the (level) camera's horizon.
  EXPECT_EQ(foreground_in(image, bottom), kWidth * 20);
  EXPECT_EQ(foreground_in(image, top), 0);
  const Rgb floor = image.pixel(kWidth / 2, kHeight - 1);
  EXPECT_TRUE(near(floor, to_rgb(renderer_->options().floor_colour), 40) ||
              near(floor, to_rgb(renderer_->options().grid_colour), 40));
}

TEST_F(HeadlessRenderTest, DebugLinesAreDrawn) {
  const DebugLine ray{Vec3(-1.0f, 0.8f, 0), Vec3(1.0f, 0.8f, 0), Colour(1, 0, 1, 1)};
  SceneView view = bare_view();
  view.lines = {&ray, 1};
  renderer_->render(view, context_->target());
  const Image image = read_pixels(context_->target());
  const Vec2 left = *project_to_pixel(view.camera, kWidth, kHeight, ray.from);
  const Vec2 right = *project_to_pixel(view.camera, kWidth, kHeight, ray.to);
  const int row = static_cast<int>(left.y());
  const auto magenta = [](const Rgb& p) { return near(p, {255, 0, 255}, 4); };
  const int on_line = count_pixels(image, {0, row - 1, kWidth, row + 2}, magenta);
  EXPECT_GT(on_line, 0.9f * (right.x() - left.x()));
  EXPECT_EQ(count_pixels(image, whole(image), magenta), on_line);
}

TEST_F(HeadlessRenderTest, WrongJointCountIsAnError) {
  std::vector<Pose> pose = arm_pose(skeleton_, Mat3::Identity(), Mat3::Identity());
  pose.pop_back();
  const AvatarDraw avatar{arm_, Pose{}, pose};
  SceneView view = bare_view();
  view.avatars = {&avatar, 1};
  try {
    renderer_->render(view, context_->target());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("2 joint poses, its mesh 3 joints"), std::string::npos)
        << e.what();
  }
  const AvatarDraw unknown{SkinnedMeshId{7}, Pose{}, pose};
  view.avatars = {&unknown, 1};
  EXPECT_THROW(renderer_->render(view, context_->target()), Error);
}

TEST_F(HeadlessRenderTest, BadSkinnedMeshIsRejectedWithItsProblem) {
  SkinnedMesh mesh = arm_mesh(skeleton_);
  mesh.joints[5][0] = 9;
  try {
    renderer_->add_skinned_mesh(mesh);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 5 references joint 9, but the mesh has 3 joints"),
              std::string::npos)
        << e.what();
  }
  mesh = arm_mesh(skeleton_);
  mesh.indices.back() = 100000;
  EXPECT_THROW(renderer_->add_skinned_mesh(mesh), Error);
  mesh = arm_mesh(skeleton_);
  mesh.weights[0] = {0.5f, 0.2f, 0.0f, 0.0f};
  EXPECT_THROW(renderer_->add_skinned_mesh(mesh), Error);
}

TEST(HeadlessContextTest, DescribesItsRendererAndRefusesBadSizes) {
  HeadlessContext context(64, 32);
  EXPECT_NE(context.description().find("EGL surfaceless"), std::string::npos);
  EXPECT_NE(context.description().find("4.5"), std::string::npos) << context.description();
  EXPECT_EQ(context.target().width, 64);
  EXPECT_EQ(context.target().height, 32);
  EXPECT_THROW(OffscreenTarget(0, 10), Error);
}

TEST(HeadlessContextTest, ContextsLiveSideBySide) {
  auto first = std::make_unique<HeadlessContext>(32, 32);
  HeadlessContext second(48, 16);  // current from here on
  const auto render_sky = [](HeadlessContext& context) {
    Renderer renderer;
    SceneView view;
    view.camera = testing::front_camera();
    renderer.render(view, context.target());
    check_gl("render");
    const Image image = read_pixels(context.target());
    return testing::near(image.pixel(0, 0), testing::to_rgb(renderer.options().background), 2);
  };
  EXPECT_TRUE(render_sky(second));
  first->make_current();
  EXPECT_TRUE(render_sky(*first));
  first.reset();  // ends only its own EGL context, not the display the second one uses
  second.make_current();
  EXPECT_TRUE(render_sky(second));
}

// People wearing the same avatar share one upload; the view's own avatar is there from the start
// and is what a null mesh (the site's default) gives; each other avatar is uploaded once, found
// again by address, and drawn; past kMaxMeshes different meshes the cache says so instead of
// uploading without bound.
TEST_F(HeadlessRenderTest, TheMeshCacheUploadsEachAvatarOnce) {
  std::vector<SkinnedMesh> meshes(SkinnedMeshCache::kMaxMeshes + 1, arm_mesh(skeleton_));
  SkinnedMeshCache cache(*renderer_, meshes[0]);
  EXPECT_EQ(cache.size(), 1u);
  const std::optional<SkinnedMeshId> first = cache.get(&meshes[0]);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->index, cache.own().index);
  EXPECT_EQ(cache.get(nullptr)->index, first->index);
  EXPECT_EQ(cache.size(), 1u);
  const std::optional<SkinnedMeshId> second = cache.get(&meshes[1]);
  ASSERT_TRUE(second.has_value());
  EXPECT_NE(second->index, first->index);
  EXPECT_NE(second->index, arm_.index);
  EXPECT_EQ(cache.get(nullptr)->index, first->index);  // the own mesh stays the default
  // The second upload draws like the fixture's own.
  const std::vector<Pose> rest = rest_model_poses(skeleton_);
  const Image expected = render_arm(rest);
  const AvatarDraw avatar{*second, Pose{}, rest};
  SceneView view = bare_view();
  view.avatars = {&avatar, 1};
  renderer_->render(view, context_->target());
  context_->present();
  EXPECT_EQ(read_pixels(context_->target()).rgb, expected.rgb);
  for (std::size_t i = 2; i < SkinnedMeshCache::kMaxMeshes; ++i) {
    ASSERT_TRUE(cache.get(&meshes[i]).has_value()) << i;
  }
  EXPECT_EQ(cache.size(), SkinnedMeshCache::kMaxMeshes);
  EXPECT_FALSE(cache.get(&meshes.back()).has_value());
  EXPECT_TRUE(cache.get(&meshes[5]).has_value());  // the known ones still answer
  EXPECT_TRUE(cache.get(nullptr).has_value());     // and the own one
}

}  // namespace
}  // namespace deixis::render
