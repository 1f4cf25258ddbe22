#include "sim/sim_input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

#include "core/io/json_reader.h"

namespace deixis::sim {

namespace {

using json = JsonReader::json;

constexpr double kClickHold = 0.1;        // s a scripted click holds its button
constexpr double kDragStep = 1.0 / 30.0;  // s between a scripted drag's moves (one tick)
constexpr int kFormatVersion = 1;
// Bounds on what a script may ask for (a script is a file, so untrusted): a drag expands into a
// move per tick, so the entries alone do not bound the events.
constexpr std::size_t kMaxEntries = 10'000;
constexpr std::size_t kMaxEvents = 200'000;  // after expansion: ~110 min of dragging at 30 Hz
constexpr std::size_t kMaxTextBytes = 256;   // a widget's label or one text event

// The command keys a window reads, in the order of WindowInput::keys_down_.
constexpr std::array<std::pair<int, char>, 4> kWindowKeys = {
    {{GLFW_KEY_E, 'e'}, {GLFW_KEY_R, 'r'}, {GLFW_KEY_P, 'p'}, {GLFW_KEY_ESCAPE, 'q'}}};

render::Vec2 read_point(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) {
    r.fail(path, "expected [x, y]");
  }
  return {r.number_in(j[0], path + "[0]", -1e5f, 1e5f),
          r.number_in(j[1], path + "[1]", -1e5f, 1e5f)};
}

render::Vec2 read_xy(const JsonReader& r, const json& j, const std::string& path) {
  return {r.number_in(r.member(j, path, "x"), path + ".x", -1e5f, 1e5f),
          r.number_in(r.member(j, path, "y"), path + ".y", -1e5f, 1e5f)};
}

Button read_button(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.contains("button")) {
    return Button::kLeft;
  }
  const std::string name = r.string(j["button"], path + ".button");
  if (name == "left") {
    return Button::kLeft;
  }
  if (name == "right") {
    return Button::kRight;
  }
  if (name == "middle") {
    return Button::kMiddle;
  }
  r.fail(path + ".button", "expected left, right or middle, found '" + name + "'");
}

bool read_shift(const JsonReader& r, const json& j, const std::string& path) {
  if (!j.contains("shift")) {
    return false;
  }
  if (!j["shift"].is_boolean()) {
    r.fail(path + ".shift", "expected true or false");
  }
  return j["shift"].get<bool>();
}

InputEvent event(double t, InputEvent::Kind kind) {
  InputEvent e;
  e.time = t;
  e.kind = kind;
  return e;
}

InputEvent move(double t, const render::Vec2& p) {
  InputEvent e = event(t, InputEvent::Kind::kMove);
  e.position = p;
  return e;
}

InputEvent button(double t, InputEvent::Kind kind, Button b, bool shift) {
  InputEvent e = event(t, kind);
  e.button = b;
  e.shift = shift;
  return e;
}

// A click aimed at a panel widget ("widget": its label) rather than at x and y.
InputEvent move_to_widget(double t, const JsonReader& r, const json& j, const std::string& path) {
  if (j.contains("x") || j.contains("y")) {
    r.fail(path + ".widget", "give either a widget or x and y, not both");
  }
  InputEvent e = event(t, InputEvent::Kind::kMove);
  e.widget = r.string(j["widget"], path + ".widget");
  if (e.widget.empty() || e.widget.size() > kMaxTextBytes) {
    r.fail(path + ".widget", "expected a widget's label of 1 to " + std::to_string(kMaxTextBytes) +
                                 " bytes, e.g. \"Start\"");
  }
  return e;
}

// What a text event types: printable ASCII, which ImGui's default font draws.
std::string read_text(const JsonReader& r, const json& j, const std::string& path) {
  std::string text = r.string(r.member(j, path, "text"), path + ".text");
  if (text.empty() || text.size() > kMaxTextBytes) {
    r.fail(path + ".text", "expected 1 to " + std::to_string(kMaxTextBytes) + " characters");
  }
  for (const char c : text) {
    if (c < ' ' || c > '~') {
      r.fail(path + ".text", "only printable ASCII characters can be typed");
    }
  }
  return text;
}

// One entry of "events", expanded into the events it stands for.
void parse_event(const JsonReader& r, const json& j, const std::string& path,
                 std::vector<InputEvent>& out) {
  // Checked as a float, read as the double it is: 0.2 s must be due at a frame at 0.2 s.
  r.number_in(r.member(j, path, "t"), path + ".t", 0.0f, 86400.0f);
  const double t = j["t"].get<double>();
  const std::string type = r.string(r.member(j, path, "type"), path + ".type");
  if (type == "move") {
    r.only_fields(j, path, {"t", "type", "x", "y"});
    out.push_back(move(t, read_xy(r, j, path)));
  } else if (type == "press" || type == "release") {
    r.only_fields(j, path, {"t", "type", "button", "shift"});
    out.push_back(button(t, type == "press" ? InputEvent::Kind::kPress : InputEvent::Kind::kRelease,
                         read_button(r, j, path), read_shift(r, j, path)));
  } else if (type == "key") {
    r.only_fields(j, path, {"t", "type", "key"});
    const std::string key = r.string(r.member(j, path, "key"), path + ".key");
    if (key.size() != 1 || std::string_view("erpq").find(key[0]) == std::string_view::npos) {
      r.fail(path + ".key",
             "expected one of e (explain), r (rest), p (look at the other "
             "person), q (quit), found '" +
                 key + "'");
    }
    InputEvent e = event(t, InputEvent::Kind::kKey);
    e.key = key[0];
    out.push_back(e);
  } else if (type == "click") {
    r.only_fields(j, path, {"t", "type", "x", "y", "widget", "button", "shift"});
    const Button b = read_button(r, j, path);
    const bool shift = read_shift(r, j, path);
    out.push_back(j.contains("widget") ? move_to_widget(t, r, j, path)
                                       : move(t, read_xy(r, j, path)));
    out.push_back(button(t, InputEvent::Kind::kPress, b, shift));
    out.push_back(button(t + kClickHold, InputEvent::Kind::kRelease, b, shift));
  } else if (type == "drag") {
    r.only_fields(j, path, {"t", "type", "from", "to", "seconds", "button", "shift"});
    const render::Vec2 from = read_point(r, r.member(j, path, "from"), path + ".from");
    const render::Vec2 to = read_point(r, r.member(j, path, "to"), path + ".to");
    r.number_in(r.member(j, path, "seconds"), path + ".seconds", 0.0f, 600.0f);
    const double seconds = j["seconds"].get<double>();
    const Button b = read_button(r, j, path);
    const bool shift = read_shift(r, j, path);
    out.push_back(move(t, from));
    out.push_back(button(t, InputEvent::Kind::kPress, b, shift));
    const int steps = std::max(1, static_cast<int>(seconds / kDragStep + 0.5));
    for (int k = 1; k <= steps; ++k) {
      const float s = static_cast<float>(k) / static_cast<float>(steps);
      out.push_back(move(t + seconds * k / steps, from + s * (to - from)));
    }
    out.push_back(button(t + seconds + kDragStep, InputEvent::Kind::kRelease, b, shift));
  } else if (type == "text") {
    r.only_fields(j, path, {"t", "type", "text"});
    InputEvent e = event(t, InputEvent::Kind::kText);
    e.text = read_text(r, j, path);
    out.push_back(e);
  } else {
    r.fail(path + ".type",
           "unknown type '" + type + "' (expected move, press, release, key, click, drag or text)");
  }
}

// Where a click aimed at a widget goes: its centre in the frame before.
render::Vec2 widget_centre(const InputEvent& e, const FindWidget& find) {
  const std::optional<render::Vec2> at = find ? find(e.widget) : std::nullopt;
  if (!at) {
    throw Error("scripted input: the click at " + std::to_string(e.time) +
                " s aims at the panel widget '" + e.widget + "', which the panel does not show");
  }
  return *at;
}

}  // namespace

void FrameInput::type(char key) {
  if (key_count < keys.size()) {
    keys[key_count++] = key;
  }
}

std::vector<InputEvent> parse_input_script(std::string_view json_text, std::string_view source) {
  const JsonReader r(source);
  const json j = r.parse_object(json_text);
  r.only_fields(j, "", {"format", "version", "events"});
  const std::string format = r.string(r.member(j, "", "format"), "format");
  if (format != "deixis-sim-input") {
    r.fail("format", "expected \"deixis-sim-input\", found \"" + format + "\"");
  }
  if (r.integer_in(r.member(j, "", "version"), "version", 0, 1000) != kFormatVersion) {
    r.fail("version", "this Deixis reads version " + std::to_string(kFormatVersion));
  }
  const json& events = r.member(j, "", "events");
  if (!events.is_array() || events.size() > kMaxEntries) {
    r.fail("events", "expected an array of at most " + std::to_string(kMaxEntries) + " entries");
  }
  std::vector<InputEvent> out;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const std::string path = "events[" + std::to_string(i) + "]";
    if (!events[i].is_object()) {
      r.fail(path, "expected an object");
    }
    parse_event(r, events[i], path, out);
    if (out.size() > kMaxEvents) {
      r.fail(path, "the script expands into more than " + std::to_string(kMaxEvents) +
                       " events (drags make one a tick)");
    }
  }
  // Stable: events at the same time keep the file's order (a click's move before its press).
  std::stable_sort(out.begin(), out.end(),
                   [](const InputEvent& a, const InputEvent& b) { return a.time < b.time; });
  return out;
}

std::vector<InputEvent> read_input_script(const std::filesystem::path& path) {
  return parse_input_script(JsonReader::read_file(path), path.string());
}

FrameInput ScriptedInput::next(double t, const FindWidget& find) {
  state_.pressed = {};
  state_.released = {};
  state_.key_count = 0;
  state_.text = {};
  for (; next_ < events_.size() && events_[next_].time <= t; ++next_) {
    const InputEvent& e = events_[next_];
    const auto b = static_cast<std::size_t>(e.button);
    switch (e.kind) {
      case InputEvent::Kind::kMove:
        state_.pointer = e.widget.empty() ? e.position : widget_centre(e, find);
        break;
      case InputEvent::Kind::kText:
        if (!state_.text.empty()) {
          return state_;  // one text a frame; the next is typed in the next frame
        }
        state_.text = e.text;
        break;
      case InputEvent::Kind::kPress:
        state_.down[b] = true;
        state_.pressed[b] = true;
        state_.shift = e.shift;
        break;
      case InputEvent::Kind::kRelease:
        state_.down[b] = false;
        state_.released[b] = true;
        break;
      case InputEvent::Kind::kKey:
        state_.type(e.key);
        break;
    }
  }
  return state_;
}

FrameInput WindowInput::next() {
  FrameInput in;
  double x = 0;
  double y = 0;
  glfwGetCursorPos(window_, &x, &y);
  in.pointer = render::Vec2(static_cast<float>(x), static_cast<float>(y));
  constexpr std::array<int, kButtons> kGlfwButtons = {
      GLFW_MOUSE_BUTTON_LEFT, GLFW_MOUSE_BUTTON_RIGHT, GLFW_MOUSE_BUTTON_MIDDLE};
  for (std::size_t b = 0; b < kButtons; ++b) {
    in.down[b] = glfwGetMouseButton(window_, kGlfwButtons[b]) == GLFW_PRESS;
    in.pressed[b] = in.down[b] && !last_.down[b];
    in.released[b] = !in.down[b] && last_.down[b];
  }
  in.shift = glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
             glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  for (std::size_t k = 0; k < kWindowKeys.size(); ++k) {
    const bool down = glfwGetKey(window_, kWindowKeys[k].first) == GLFW_PRESS;
    if (down && !keys_down_[k]) {
      in.type(kWindowKeys[k].second);
    }
    keys_down_[k] = down;
  }
  last_ = in;
  return in;
}

}  // namespace deixis::sim
