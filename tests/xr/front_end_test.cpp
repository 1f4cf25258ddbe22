// The OpenXR front end (xr/) through the project's test runtime and Debian's real loader with
// XR_APILAYER_LUNARG_core_validation: an OpenGL session on the renderer's EGL context runs a
// scripted user to the end; every frame is submitted in order at its predicted display time with
// both views rendered into the swapchains (the runtime's record); the scripted head, gaze and
// hand poses arrive as TrackingFrames (1 mm / 0.1°); the layer reports nothing. The same with
// controllers instead of hand tracking, and the pose conversions on their own.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/headless_context.h"
#include "render/image.h"
#include "render/offscreen_target.h"
#include "render/renderer.h"
#include "tests/xr/session_run.h"
#include "tests/xr/xr_fixture.h"
#include "xr/frame_loop.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

namespace deixis::xr {
namespace {

namespace fs = std::filesystem;

constexpr float kDeg = 3.14159265f / 180.0f;

float angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// The scripted right wrist: turned 30° about +Y and 20° about its own +X, so a wrong axis
// mapping shows.
const Quat kRightWrist =
    Quat(Eigen::AngleAxisf(30 * kDeg, Vec3::UnitY()) * Eigen::AngleAxisf(20 * kDeg, Vec3::UnitX()));

class FrontEnd : public XrRuntimeTest {
 protected:
  FrontEnd() : XrRuntimeTest("deixis_xr_front_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    nlohmann::json wrist = {
        {"position", {0.2, 1.1, -0.3}},
        {"orientation", {kRightWrist.x(), kRightWrist.y(), kRightWrist.z(), kRightWrist.w()}}};
    nlohmann::json script = {
        {"display_hz", 90},
        {"frames", 20},
        {"keys",
         {{{"t", 0},
           {"head", {{"position", {0.1, 1.6, 0.05}}, {"orientation", {0, 0, 0, 1}}}},
           {"gaze", {0, -0.2, -1}},
           {"right", {{"wrist", wrist}, {"index_tip", {0.15, 1.05, -0.48}}}},
           {"left", nullptr}}}}};
    write_script(script.dump());
  }
};

// Keeps what the loop hands it; renders every view with the real renderer.
class RecordingSink final : public FrameSink {
 public:
  explicit RecordingSink(render::Renderer& renderer) : renderer_(renderer) { frames.reserve(256); }
  void on_frame(const FrameInfo& info, const TrackingFrame& user) override {
    frames.push_back({info, user});
  }
  void render_view(std::uint32_t view, const render::Camera& camera,
                   const render::RenderTarget& target) override {
    render::SceneView scene;
    scene.camera = camera;
    renderer_.render(scene, target);
    ++rendered;
    last_eye[view] = camera.T_world_eye.translation;
  }
  struct Seen {
    FrameInfo info;
    TrackingFrame user;
  };
  std::vector<Seen> frames;
  int rendered = 0;
  std::array<Vec3, 2> last_eye = {Vec3::Zero(), Vec3::Zero()};

 private:
  render::Renderer& renderer_;
};

struct RunResult {
  FrameLoopResult loop;
  std::vector<RecordingSink::Seen> frames;
  int rendered = 0;
  std::array<Vec3, 2> last_eye;
  bool hand_tracking = false;
  bool eye_gaze = false;
  std::uint64_t gaze_from_head_frames = 0;
};

RunResult run_session(bool headless) {
  render::HeadlessContext context(16, 16);
  render::Renderer renderer;
  RecordingSink sink(renderer);
  const SessionRun run = run_session_with(headless, sink);
  RunResult out;
  out.loop = run.loop;
  out.frames = sink.frames;
  out.rendered = sink.rendered;
  out.last_eye = sink.last_eye;
  out.hand_tracking = run.hand_tracking;
  out.eye_gaze = run.eye_gaze;
  out.gaze_from_head_frames = run.gaze_from_head_frames;
  return out;
}

void expect_scripted_user(const RunResult& r, bool hand_tracking) {
  int gaze_frames = 0;
  for (const auto& seen : r.frames) {
    const TrackingFrame& f = seen.user;
    ASSERT_TRUE(f.valid & tracked::kHead) << "frame " << seen.info.index;
    EXPECT_LT((f.T_world_head.translation - Vec3(0.1f, 1.6f, 0.05f)).norm(), 1e-3f);
    EXPECT_FALSE(f.valid & tracked::kLeftHand) << "the left hand is untracked in the script";
    if (f.valid & tracked::kGaze) {
      ++gaze_frames;
      EXPECT_LT(angle_between(f.gaze, Vec3(0, -0.2f, -1)), 0.1f * kDeg);
    }
    if (!hand_tracking && seen.info.state != SessionState::kFocused) {
      continue;  // controller poses need xrSyncActions, which needs focus
    }
    ASSERT_TRUE(f.valid & tracked::kRightHand) << "frame " << seen.info.index;
    EXPECT_LT((f.index_tip[1] - Vec3(0.15f, 1.05f, -0.48f)).norm(), 1e-3f);
    EXPECT_LT((f.T_world_wrist[1].translation - Vec3(0.2f, 1.1f, -0.3f)).norm(), 1e-3f);
    // §7: right wrist x distal (joint −Z), y dorsal (+Y), z ulnar (+X).
    const Mat3 R = kRightWrist.toRotationMatrix();
    EXPECT_LT(angle_between(f.T_world_wrist[1].rotation.col(0), -R.col(2)), 0.1f * kDeg);
    EXPECT_LT(angle_between(f.T_world_wrist[1].rotation.col(1), R.col(1)), 0.1f * kDeg);
    EXPECT_LT(angle_between(f.T_world_wrist[1].rotation.col(2), R.col(0)), 0.1f * kDeg);
  }
  EXPECT_GT(gaze_frames, 0) << "no frame had the eye gaze";
}

void expect_frames_in_order(const nlohmann::json& rec, const RunResult& r, int views) {
  ASSERT_EQ(rec["frames"].size(), r.loop.frames);
  ASSERT_EQ(r.frames.size(), r.loop.frames);
  long long previous = 0;
  for (std::size_t i = 0; i < rec["frames"].size(); ++i) {
    const auto& f = rec["frames"][i];
    EXPECT_EQ(f["index"].get<std::size_t>(), i);
    EXPECT_EQ(f["submitted_display_time"], f["predicted_display_time"]);
    EXPECT_EQ(f["predicted_display_time"].get<long long>(),
              static_cast<long long>(r.frames[i].info.predicted_display_time));
    EXPECT_GT(f["predicted_display_time"].get<long long>(), previous);
    previous = f["predicted_display_time"].get<long long>();
    // A layer with every view exactly when the runtime said shouldRender.
    const int expected = r.frames[i].info.should_render ? views : 0;
    EXPECT_EQ(f["layers"].get<int>(), expected > 0 ? 1 : 0) << "frame " << i;
    EXPECT_EQ(f["projection_views"].get<int>(), expected) << "frame " << i;
  }
  EXPECT_EQ(rec["refusals"].size(), 0u) << rec["refusals"].dump();
  ASSERT_FALSE(rec["states"].empty());
  EXPECT_EQ(rec["states"].back(), "EXITING");
}

// Under core validation: Debian 12's layer (1.0.20) does not know XrGraphicsBindingEGLMNDX and
// refuses any session carrying it (VUID-XrSessionCreateInfo-next-next) without calling down, so
// the validated run is headless (everything but the swapchains); the OpenGL runs below go
// through the loader without the layer (docs/decisions.md §43).
TEST_F(FrontEnd, HeadlessSessionUnderValidationDeliversTheScriptedUserInOrder) {
  const RunResult r = run_session(true);
  EXPECT_TRUE(r.hand_tracking);
  EXPECT_TRUE(r.eye_gaze);
  EXPECT_EQ(r.loop.frames, 20u);
  EXPECT_FALSE(r.loop.lost);
  EXPECT_EQ(r.rendered, 0);
  expect_scripted_user(r, true);
  const nlohmann::json rec = record();
  expect_frames_in_order(rec, r, 0);
  EXPECT_EQ(rec["interaction"], "hand_tracking");
  EXPECT_TRUE(rec["gaze_bound"].get<bool>());
  EXPECT_EQ(validation_messages(), "");
}

TEST_F(FrontEnd, ControllerPathUnderValidation) {
  setenv("DEIXIS_XR_HIDE_EXTENSIONS", "XR_EXT_hand_tracking", 1);
  const RunResult r = run_session(true);
  EXPECT_FALSE(r.hand_tracking);
  EXPECT_EQ(r.loop.frames, 20u);
  expect_scripted_user(r, false);
  const nlohmann::json rec = record();
  expect_frames_in_order(rec, r, 0);
  EXPECT_EQ(rec["interaction"], "controllers");
  // Actions are synced once per frame, and only with focus.
  int synced = 0;
  for (const auto& f : rec["frames"]) {
    EXPECT_LE(f["synced_actions"].get<int>(), 1);
    synced += f["synced_actions"].get<int>();
  }
  EXPECT_GT(synced, 0);
  EXPECT_EQ(validation_messages(), "");
}

// A runtime without eye tracking (Monado's devices, many headsets): the gaze is estimated as
// the head's forward on every frame with the head (decision 79), never left out, and counted
// as estimated. The head is turned and the scripted eyes look elsewhere, so neither a fixed
// forward nor the eyes' gaze passes.
TEST_F(FrontEnd, WithoutEyeGazeTheGazeIsTheHeadsForwardCountedAsEstimated) {
  const Quat head = Quat(Eigen::AngleAxisf(25 * kDeg, Vec3::UnitY()) *
                         Eigen::AngleAxisf(-10 * kDeg, Vec3::UnitX()));
  nlohmann::json script = {{"display_hz", 90},
                           {"frames", 20},
                           {"keys",
                            {{{"t", 0},
                              {"head",
                               {{"position", {0.1, 1.6, 0.05}},
                                {"orientation", {head.x(), head.y(), head.z(), head.w()}}}},
                              {"gaze", {0, -0.2, -1}},
                              {"right", nullptr},
                              {"left", nullptr}}}}};
  write_script(script.dump());
  setenv("DEIXIS_XR_HIDE_EXTENSIONS", "XR_EXT_eye_gaze_interaction", 1);
  const RunResult r = run_session(true);
  EXPECT_FALSE(r.eye_gaze);
  ASSERT_EQ(r.loop.frames, 20u);
  const Vec3 forward = head * Vec3(0, 0, -1);
  ASSERT_GT(angle_between(forward, Vec3(0, -0.2f, -1)), 20 * kDeg);
  for (const auto& seen : r.frames) {
    const TrackingFrame& f = seen.user;
    ASSERT_TRUE(f.valid & tracked::kHead) << "frame " << seen.info.index;
    ASSERT_TRUE(f.valid & tracked::kGaze) << "frame " << seen.info.index;
    EXPECT_LT(angle_between(f.gaze, forward), 0.1f * kDeg) << "frame " << seen.info.index;
  }
  EXPECT_EQ(r.gaze_from_head_frames, r.loop.frames);
  EXPECT_FALSE(record()["gaze_bound"].get<bool>());
  EXPECT_EQ(validation_messages(), "");
}

// With eye tracking the eyes' gaze is used and nothing is estimated.
TEST_F(FrontEnd, WithEyeGazeNothingIsEstimated) {
  const RunResult r = run_session(true);
  EXPECT_TRUE(r.eye_gaze);
  EXPECT_EQ(r.gaze_from_head_frames, 0u);
}

TEST_F(FrontEnd, OpenGlSessionRendersBothViewsInOrderAndDeliversTheScriptedUser) {
  unsetenv("XR_ENABLE_API_LAYERS");
  const RunResult r = run_session(false);
  EXPECT_TRUE(r.hand_tracking);
  EXPECT_TRUE(r.eye_gaze);
  EXPECT_EQ(r.loop.frames, 20u);
  EXPECT_FALSE(r.loop.lost);
  int should_render = 0;
  for (const auto& seen : r.frames) {
    should_render += seen.info.should_render ? 1 : 0;
  }
  EXPECT_GE(should_render, 15);  // all but the frames outside VISIBLE / FOCUSED
  EXPECT_EQ(r.rendered, 2 * should_render);
  EXPECT_EQ(r.loop.rendered_views, static_cast<std::uint64_t>(2 * should_render));
  EXPECT_NEAR((r.last_eye[1] - r.last_eye[0]).norm(), 0.063f, 1e-4f);  // the script's IPD
  expect_scripted_user(r, true);
  const nlohmann::json rec = record();
  expect_frames_in_order(rec, r, 2);
  EXPECT_EQ(rec["interaction"], "hand_tracking");
}

// Renders each view twice, into the swapchain image and into an offscreen RGBA8 target the
// desktop and headless paths use, and keeps both read-backs of the last frame.
class ComparingSink final : public FrameSink {
 public:
  explicit ComparingSink(render::Renderer& renderer) : renderer_(renderer) {}
  void on_frame(const FrameInfo&, const TrackingFrame&) override {}
  void render_view(std::uint32_t, const render::Camera& camera,
                   const render::RenderTarget& target) override {
    render::SceneView scene;
    scene.camera = camera;
    renderer_.render(scene, target);
    swapchain_image = render::read_pixels(target);
    render::OffscreenTarget offscreen(target.width, target.height);
    renderer_.render(scene, offscreen.target());
    desktop_image = render::read_pixels(offscreen.target());
  }
  render::Image swapchain_image, desktop_image;

 private:
  render::Renderer& renderer_;
};

// The headset shows what the desktop shows: the renderer's display-referred bytes go into the
// sRGB swapchain unconverted (decision 47); with sRGB encoding on write they would not.
TEST_F(FrontEnd, TheSrgbSwapchainHoldsTheDesktopsBytes) {
  unsetenv("XR_ENABLE_API_LAYERS");
  render::HeadlessContext context(16, 16);
  render::Renderer renderer;
  ComparingSink sink(renderer);
  EXPECT_EQ(run_session_with(false, sink).swapchain_format, GL_SRGB8_ALPHA8);
  const render::Image& a = sink.swapchain_image;
  const render::Image& b = sink.desktop_image;
  ASSERT_GT(a.width, 0);
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  int worst = 0;
  int darkest = 255;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    worst = std::max(worst, std::abs(int{a.rgb[i]} - int{b.rgb[i]}));
    darkest = std::min(darkest, int{b.rgb[i]});
  }
  EXPECT_LE(worst, 1);
  EXPECT_LT(darkest, 200);  // mid-tones present: an sRGB encoding would have moved them
}

TEST(XrPoses, NonFiniteOrNonUnitPosesAreRefused) {
  XrPosef p{{0, 0, 0, 1}, {0, 1, 0}};
  EXPECT_TRUE(to_pose(p).has_value());
  p.position.y = std::nanf("");
  EXPECT_FALSE(to_pose(p).has_value());
  p.position.y = 1;
  p.orientation.w = 0.5f;
  EXPECT_FALSE(to_pose(p).has_value());
  p.orientation.w = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(to_pose(p).has_value());
}

TEST(XrPoses, WristFramesFollowDecisionSeven) {
  // Palms down, fingers along −Z (the joints' identity): the right hand's ulnar side is +X, the
  // left's −X; distal is −Z for both, so the left's proximal x is +Z.
  const Pose joint{Mat3::Identity(), Vec3(0, 1, 0)};
  const Pose right = wrist_from_joint(joint, Hand::kRight);
  const Pose left = wrist_from_joint(joint, Hand::kLeft);
  EXPECT_TRUE(right.rotation.col(0).isApprox(Vec3(0, 0, -1)));
  EXPECT_TRUE(right.rotation.col(1).isApprox(Vec3(0, 1, 0)));
  EXPECT_TRUE(right.rotation.col(2).isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(left.rotation.col(0).isApprox(Vec3(0, 0, 1)));
  EXPECT_TRUE(left.rotation.col(1).isApprox(Vec3(0, 1, 0)));
  EXPECT_TRUE(left.rotation.col(2).isApprox(Vec3(-1, 0, 0)));
  EXPECT_NEAR(right.rotation.determinant(), 1.0f, 1e-6f);
  EXPECT_NEAR(left.rotation.determinant(), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace deixis::xr
