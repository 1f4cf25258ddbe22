#pragma once
// Dear ImGui on the simulator's window, with Debian's libimgui backends used as they are
// (GLFW for input, OpenGL 3 for drawing). One per window; needs its GL context current.
// Scripted input (--input) replaces the backend's mouse state for the frame and types its text
// into the panel, so a scripted run clicks and fills the panel exactly as a person would.

#include "sim/sim_input.h"

struct GLFWwindow;

namespace deixis::sim {

class ImGuiLayer {
 public:
  // Throws deixis::Error when a backend cannot start.
  explicit ImGuiLayer(GLFWwindow* window);
  ~ImGuiLayer();
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // Begins a frame; `scripted`, when given, is the mouse the UI sees and the text it is typed.
  void begin_frame(const FrameInput* scripted);
  // Draws what the frame built over the current framebuffer (the window's back buffer).
  void render();

  // Whether the UI wants the mouse / keyboard this frame (over the panel, typing in a field).
  bool wants_mouse() const;
  bool wants_keyboard() const;
};

}  // namespace deixis::sim
