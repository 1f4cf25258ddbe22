// The headset check: a user wearing a headset points at (or touches) object X in room A and
// the remote site's avatar points at (touches) X's copy in room B. The user is a synthetic test
// subject (capture/, never the training subject) performed as the project's OpenXR test runtime's
// scripted head, eye gaze and hand joints; the front end (xr/) reads them back through Debian's
// loader with core validation as tracking frames; the site selects the targets from that tracking
// (gesture/target_selection.h, no labels); the remote avatar translates them into room B
// (tests/presence/deictic_check.h). Errors as there: HE, VE ≤ 5°, touch ≤ 3 cm, copy-paste
// far worse.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "avatar/avatar_loader.h"
#include "presence/deictic_check.h"
#include "render/headless_context.h"
#include "test_support.h"
#include "tests/xr/runtime_script.h"
#include "tests/xr/session_run.h"
#include "tests/xr/xr_fixture.h"

namespace deixis::xr {
namespace {

namespace fs = std::filesystem;

// Keeps each frame's tracking.
class TrackingRecorder final : public FrameSink {
 public:
  explicit TrackingRecorder(std::size_t frames) { tracking.reserve(frames); }
  void on_frame(const FrameInfo&, const TrackingFrame& user) override { tracking.push_back(user); }
  void render_view(std::uint32_t, const render::Camera&, const render::RenderTarget&) override {}
  std::vector<TrackingFrame> tracking;
};

class HeadsetPointAt : public XrRuntimeTest {
 protected:
  HeadsetPointAt() : XrRuntimeTest("deixis_xr_point_") {}

  // The tracking a headset site reads for a performed sequence, with targets selected from it.
  std::vector<TrackingFrame> through_the_headset(const capture::Sequence& s) {
    write_script(runtime_script(s.frames, false));
    render::HeadlessContext context(16, 16);
    TrackingRecorder recorder(s.size());
    const SessionRun run = run_session_with(true, recorder);
    EXPECT_FALSE(run.loop.lost);
    EXPECT_TRUE(run.hand_tracking);
    for (const TrackingFrame& f : recorder.tracking) {
      gaze_frames_ += (f.valid & tracked::kGaze) != 0 ? 1 : 0;
    }
    frames_ += recorder.tracking.size();
    return presence::with_selected_targets(s, std::move(recorder.tracking));
  }

  static ik::AvatarSolver default_avatar() {
    return ik::AvatarSolver::build(
        avatar::load_avatar(fs::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb").rig);
  }

  void check(const char* subject) {
    const fs::path weights = testing::reference_dir() / "weights";
    const auto source = [this](const capture::Sequence& s) { return through_the_headset(s); };
    const ik::AvatarSolver solver = default_avatar();
    const presence::DeicticOutcome pointing = presence::run_deictic_check(
        subject, capture::Category::kPointingSingle, 6, solver, weights, source);
    presence::report((std::string(subject) + " pointing through the headset").c_str(), pointing);
    presence::expect_pointing(pointing);
    const presence::DeicticOutcome touching = presence::run_deictic_check(
        subject, capture::Category::kTouchingSingle, 6, solver, weights, source);
    presence::report((std::string(subject) + " touching through the headset").c_str(), touching);
    presence::expect_touching(touching);
    // The eyes were tracked (once the session had focus), and the layer found nothing wrong.
    EXPECT_GT(gaze_frames_, frames_ * 9 / 10);
    EXPECT_EQ(validation_messages(), "");
  }

  std::size_t frames_ = 0, gaze_frames_ = 0;
};

TEST_F(HeadsetPointAt, RightHandedUsersAvatarPointsAndTouchesAtRoomBsCopy) {
  check("172");
}

TEST_F(HeadsetPointAt, LeftHandedUsersAvatarPointsAndTouchesAtRoomBsCopy) {
  check("173");
}

}  // namespace
}  // namespace deixis::xr
