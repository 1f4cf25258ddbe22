#pragma once
// `deixis xr --setup`: the room's target map set up from inside the headset (docs/xr.md
// "Setting up the room", decision 85). The frame sink edits the map through site::RoomSetup from
// the user's tracking and the controllers' buttons, shows every object as an outline (the current
// one brighter, a marked pointing ray as a line) and a head-locked panel saying what to do, and
// saves the map after every completed edit.
//
// Controls (the deictic hand is --hand's; the other hand the other one):
//   deictic select  use the tool (touch: place or grab and move; point: mark a ray; resize: hold)
//   deictic menu    next tool
//   other select    next object
//   other menu      recalibrate the upright posture (stand upright, look ahead)

#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/tracking.h"
#include "gesture/upright_calibration.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "site/room_setup.h"
#include "xr/frame_loop.h"

namespace deixis::app {

// The head-locked panel (setup's and the presence panel): 0.55 m ahead of the eyes and 0.2 m
// below them (20° down, out of the way of what the user looks at), facing them; lines 2 cm tall
// (2°: about 40 px on a current headset).
inline const Pose kHeadPanel{Mat3::Identity(), Vec3(0.0f, -0.2f, -0.55f)};
inline constexpr float kPanelLineHeight = 0.02f;

// The recalibrate button (the other hand's menu) went down this frame.
bool recalibrate_pressed(const xr::Buttons& buttons, Hand deictic_hand);
// The user's upright posture now, printed as "calibrated: ..." (or "recalibrated: ..."); throws
// deixis::Error as calibrate_upright does (the head not tracked, a body out of human range).
BodyCalibration calibrate_and_tell(const TrackingFrame& user, const UprightBody& body, bool again);

class SetupSink final : public xr::FrameSink {
 public:
  // Edits `setup`'s map (the site's, checked when it was made); saves to `save` (the site's
  // target map file by default: later sessions read it), the file it replaces kept once as
  // `<save>.bak`.
  SetupSink(site::RoomSetup setup, std::filesystem::path save, const UprightBody& body,
            render::Renderer& renderer, bool see_through, bool panel);

  void on_frame(const xr::FrameInfo& frame, const TrackingFrame& user) override;
  void render_view(std::uint32_t view, const render::Camera& camera,
                   const render::RenderTarget& target) override;

  // What was set up, and where it went; false when edits are left unsaved (the last save
  // failed), whose objects it prints as they were set.
  bool print_summary() const;

 private:
  void save();
  void refresh_panel();
  void build_outlines();

  site::RoomSetup setup_;
  std::filesystem::path save_;
  Hand hand_;
  UprightBody body_;
  render::Renderer& renderer_;
  bool see_through_;
  bool show_panel_;
  bool calibrated_ = false;
  bool backed_up_ = false;
  std::uint64_t saved_edits_ = 0;
  std::uint64_t save_events_ = 0;  // saves and failures: the panel's last line changes
  std::string save_status_ = "not saved yet: nothing changed";
  Pose head_{};
  std::vector<render::DebugLine> lines_;  // every object's outline and a marked ray
  std::size_t line_count_ = 0;
  std::array<std::string, 5> panel_text_;
  std::array<std::string_view, 5> panel_lines_;
  render::HeadPanel panel_;
  // What the panel last showed (rebuilt only when one of these changes).
  std::size_t shown_object_ = static_cast<std::size_t>(-1);
  site::SetupTool shown_tool_ = site::SetupTool::kTouch;
  std::string shown_message_;
  std::uint64_t shown_save_events_ = static_cast<std::uint64_t>(-1);
};

}  // namespace deixis::app
