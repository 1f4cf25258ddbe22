#pragma once
// The simulator's input, frame by frame (docs/sim.md): the mouse pointer (window pixels, row 0 at
// the top), its buttons with the presses and releases since the last frame, the shift key, and
// the command keys typed. Two sources give the same FrameInput: the window (GLFW, a person) and
// a scripted input file (`--input`, JSON: timed events), so tests drive the simulator exactly as a
// person would, without one.
//
// A scripted input file:
//   {"format": "deixis-sim-input", "version": 1, "events": [
//     {"t": 0.5, "type": "move", "x": 320, "y": 200},
//     {"t": 0.6, "type": "press", "button": "left", "shift": false},
//     {"t": 0.7, "type": "release", "button": "left"},
//     {"t": 1.0, "type": "key", "key": "e"},
//     {"t": 2.0, "type": "click", "x": 320, "y": 200, "button": "left", "shift": true},
//     {"t": 3.0, "type": "drag", "from": [900, 240], "to": [1000, 260], "seconds": 0.5},
//     {"t": 4.0, "type": "click", "widget": "avatar path"},
//     {"t": 4.2, "type": "text", "text": "assets/avatars/default.glb"}]}
// "t" is seconds of simulator time; a click presses at t and releases 0.1 s later; a drag presses
// at `from`, moves in steps of a tick to `to` over `seconds` and releases a tick after. A click
// may aim at a panel widget by its label instead of x and y: the pointer goes to the widget's
// centre where the frame before drew it, and ImGui takes the click as a person's. A text event
// types its characters (printable ASCII) into the panel's field that has the keyboard.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "render/camera.h"

struct GLFWwindow;

namespace deixis::sim {

enum class Button : std::uint8_t { kLeft = 0, kRight = 1, kMiddle = 2 };
inline constexpr std::size_t kButtons = 3;

struct FrameInput {
  render::Vec2 pointer = render::Vec2::Zero();
  std::array<bool, kButtons> down{};      // held now
  std::array<bool, kButtons> pressed{};   // went down since the last frame
  std::array<bool, kButtons> released{};  // went up since the last frame
  bool shift = false;
  std::array<char, 8> keys{};  // command keys typed since the last frame, lower case
  std::size_t key_count = 0;
  std::string_view text;  // scripted: characters typed into the panel this frame

  bool is_down(Button b) const { return down[static_cast<std::size_t>(b)]; }
  bool was_pressed(Button b) const { return pressed[static_cast<std::size_t>(b)]; }
  bool was_released(Button b) const { return released[static_cast<std::size_t>(b)]; }
  void type(char key);  // adds a key (ignored beyond the array)
};

struct InputEvent {
  enum class Kind : std::uint8_t { kMove, kPress, kRelease, kKey, kText };
  double time = 0.0;
  Kind kind = Kind::kMove;
  render::Vec2 position = render::Vec2::Zero();  // kMove
  std::string widget;                            // kMove: to this panel widget instead
  Button button = Button::kLeft;                 // kPress, kRelease
  bool shift = false;                            // kPress
  char key = 0;                                  // kKey
  std::string text;                              // kText
};

// The centre of the panel widget labelled so, in window pixels, where the last frame drew it;
// nullopt when it drew none.
using FindWidget = std::function<std::optional<render::Vec2>(std::string_view label)>;

// Parses a scripted input file into events sorted by time (clicks and drags expanded). Throws
// deixis::Error naming `source` and the field, e.g. "in.json: events[2].button: expected left,
// right or middle".
std::vector<InputEvent> parse_input_script(std::string_view json_text, std::string_view source);
std::vector<InputEvent> read_input_script(const std::filesystem::path& path);

// Plays scripted events into frames.
class ScriptedInput {
 public:
  explicit ScriptedInput(std::vector<InputEvent> events) : events_(std::move(events)) {}
  // The input of the frame at time `t`: every event up to `t` not yet played (a second text
  // event waits for the next frame). Moves to a widget are aimed with `find`; throws
  // deixis::Error when it finds no such widget.
  FrameInput next(double t, const FindWidget& find = {});
  bool finished() const { return next_ == events_.size(); }

 private:
  std::vector<InputEvent> events_;
  std::size_t next_ = 0;
  FrameInput state_;
};

// Reads a window's pointer, buttons and command keys (call after glfwPollEvents).
class WindowInput {
 public:
  explicit WindowInput(GLFWwindow* window) : window_(window) {}
  FrameInput next();

 private:
  GLFWwindow* window_;
  FrameInput last_;
  std::array<bool, 4> keys_down_{};
};

}  // namespace deixis::sim
