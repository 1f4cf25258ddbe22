#include "app/xr_setup.h"

#include <cstdio>
#include <system_error>

#include "core/error.h"
#include "render/outline.h"

namespace deixis::app {

namespace {

namespace fs = std::filesystem;

constexpr double kRayLengthM = 4.0;  // a marked pointing ray, drawn this far
const render::Colour kCurrentColour(1.0f, 1.0f, 1.0f, 1.0f);
const render::Colour kRayColour(1.0f, 0.9f, 0.1f, 1.0f);

std::size_t other_index(Hand hand) {
  return static_cast<std::size_t>(index(other(hand)));
}

const char* hand_word(std::size_t i) {
  return i == static_cast<std::size_t>(index(Hand::kLeft)) ? "left" : "right";
}

}  // namespace

bool recalibrate_pressed(const xr::Buttons& buttons, Hand deictic_hand) {
  return buttons.menu_pressed[other_index(deictic_hand)];
}

BodyCalibration calibrate_and_tell(const TrackingFrame& user, const UprightBody& body, bool again) {
  const BodyCalibration calibration = calibrate_upright(user, body);
  std::printf("%s: stature %.2f m, arm %.2f m, %s hand\n", again ? "recalibrated" : "calibrated",
              static_cast<double>(calibration.height), static_cast<double>(calibration.arm_length),
              calibration.deictic_hand == Hand::kLeft ? "left" : "right");
  std::fflush(stdout);
  return calibration;
}

SetupSink::SetupSink(site::RoomSetup setup, fs::path save, const UprightBody& body,
                     render::Renderer& renderer, bool see_through, bool panel)
    : setup_(std::move(setup)),
      save_(std::move(save)),
      hand_(body.deictic_hand),
      body_(body),
      renderer_(renderer),
      see_through_(see_through),
      show_panel_(panel) {
  // Room for every object's outline and the ray, once: nothing grows per frame.
  lines_.resize(setup_.map().objects.size() * render::kMaxOutlineLines + 1);
  refresh_panel();  // the panel's first text (nothing shown yet: every field differs)
  build_outlines();
}

void SetupSink::on_frame(const xr::FrameInfo& frame, const TrackingFrame& user) {
  if ((user.valid & tracked::kHead) != 0) {
    head_ = user.T_world_head;
    try {
      if (!calibrated_ || recalibrate_pressed(frame.buttons, hand_)) {
        calibrate_and_tell(user, body_, calibrated_);
        calibrated_ = true;
      }
    } catch (const Error& e) {
      std::fprintf(stderr, "deixis xr: cannot calibrate: %s\n", e.what());
    }
  }
  const std::size_t d = static_cast<std::size_t>(index(hand_));
  const site::SetupControls controls{
      .act = frame.buttons.select[d],
      .act_pressed = frame.buttons.select_pressed[d],
      .next_tool = frame.buttons.menu_pressed[d],
      .next_object = frame.buttons.select_pressed[other_index(hand_)]};
  if (setup_.update(user, controls)) {
    save();
  }
  refresh_panel();
  build_outlines();
}

// After every completed edit, so a session that ends (or a runtime that dies) loses nothing.
void SetupSink::save() {
  ++save_events_;
  try {
    std::error_code ec;
    if (!backed_up_ && fs::exists(save_, ec)) {
      fs::path backup = save_;
      backup += ".bak";
      fs::copy_file(save_, backup, fs::copy_options::overwrite_existing, ec);
      if (ec) {
        throw Error(backup.string() + ": cannot keep the previous map: " + ec.message());
      }
    }
    backed_up_ = true;
    write_target_map(setup_.map(), save_);
    saved_edits_ = setup_.edits();
    save_status_ = "saved " + save_.filename().string() + " (" + std::to_string(saved_edits_) +
                   (saved_edits_ == 1 ? " edit)" : " edits)");
  } catch (const Error& e) {
    save_status_ = std::string("NOT SAVED: ") + e.what();
    std::fprintf(stderr, "deixis xr: %s\n", save_status_.c_str());
  }
}

void SetupSink::refresh_panel() {
  if (shown_object_ == setup_.current_index() && shown_tool_ == setup_.tool() &&
      shown_message_ == setup_.message() && shown_save_events_ == save_events_) {
    return;  // unchanged: the panel keeps its text (and the renderer its geometry)
  }
  shown_object_ = setup_.current_index();
  shown_tool_ = setup_.tool();
  shown_message_ = setup_.message();
  shown_save_events_ = save_events_;
  const std::size_t d = static_cast<std::size_t>(index(hand_));
  panel_text_[0] = "Setup: " + setup_.current().name + " (" +
                   std::to_string(setup_.current_index() + 1) + " of " +
                   std::to_string(setup_.map().objects.size()) + "), " +
                   std::string(site::setup_tool_name(setup_.tool())) + " tool";
  panel_text_[1] = setup_.message();
  panel_text_[2] =
      std::string(hand_word(d)) + " select: use the tool, " + hand_word(d) + " menu: next tool";
  panel_text_[3] = std::string(hand_word(other_index(hand_))) + " select: next object, " +
                   hand_word(other_index(hand_)) + " menu: recalibrate";
  panel_text_[4] = save_status_;
  for (std::size_t i = 0; i < panel_lines_.size(); ++i) {
    panel_lines_[i] = panel_text_[i];
  }
}

void SetupSink::build_outlines() {
  const std::span<render::DebugLine> all(lines_);
  std::size_t n = 0;
  const auto& objects = setup_.map().objects;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const render::Colour colour =
        i == setup_.current_index() ? kCurrentColour : render::target_colour(objects[i].id);
    n += render::outline(objects[i], colour, all.subspan(n));
  }
  if (const auto& ray = setup_.first_ray()) {
    all[n++] = {ray->origin + ray->direction * 0.3f,
                ray->origin + ray->direction * static_cast<float>(kRayLengthM), kRayColour};
  }
  line_count_ = n;
}

void SetupSink::render_view(std::uint32_t, const render::Camera& camera,
                            const render::RenderTarget& target) {
  render::SceneView view;
  view.camera = camera;
  view.show_floor = !see_through_;
  view.show_targets = false;  // the outlines show where they are; the real objects are there
  view.lines = std::span<const render::DebugLine>(lines_.data(), line_count_);
  if (show_panel_) {
    panel_.T_world_panel = compose(head_, kHeadPanel);
    panel_.lines = panel_lines_;
    panel_.line_height = kPanelLineHeight;
    view.panel = &panel_;
  }
  renderer_.render(view, target);
}

bool SetupSink::print_summary() const {
  const auto edits = static_cast<unsigned long long>(setup_.edits());
  const auto unsaved = edits - static_cast<unsigned long long>(saved_edits_);
  if (edits == 0) {
    std::printf("setup: 0 edits, %s left as it was\n", save_.string().c_str());
  } else if (unsaved == 0) {
    std::printf("setup: %llu edits, saved to %s\n", edits, save_.string().c_str());
  } else {
    // The last save failed (said on the panel and stderr as it happened); the objects as set are
    // printed below, so that nothing the user did is lost.
    std::printf("setup: %llu edits, the last %llu NOT SAVED to %s (%s); the objects as set:\n",
                edits, unsaved, save_.string().c_str(), save_status_.c_str());
  }
  for (const TargetObject& o : setup_.map().objects) {
    std::printf("object %d %s: position [%.3f, %.3f, %.3f], size [%.3f, %.3f, %.3f]\n", o.id,
                o.name.c_str(), static_cast<double>(o.position.x()),
                static_cast<double>(o.position.y()), static_cast<double>(o.position.z()),
                static_cast<double>(o.size.x()), static_cast<double>(o.size.y()),
                static_cast<double>(o.size.z()));
  }
  return unsaved == 0;
}

}  // namespace deixis::app
