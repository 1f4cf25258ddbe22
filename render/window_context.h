#pragma once
// A desktop window (GLFW 3.3) with an OpenGL 4.5 core context, for the desktop simulator: frames
// are drawn into the window's back buffer and shown by present(). glfw_window() hands the window
// to Dear ImGui's GLFW backend. GLFW is process-wide: the first WindowContext initialises it and
// it stays initialised until the process exits, because glfwTerminate would close every other
// window too and unload the GL driver (whose still-referenced allocations LeakSanitizer then
// reports as leaks it cannot attribute). Several windows may exist side by side; GLFW wants them
// created, polled and destroyed on the main thread.

#include <string>

#include "render/context.h"

struct GLFWwindow;

namespace deixis::render {

struct WindowOptions {
  int width = 1280;
  int height = 720;
  std::string title = "Deixis";
  bool visible = true;
  bool vsync = true;
};

class WindowContext final : public Context {
 public:
  // Throws deixis::Error with GLFW's own reason (no display, no OpenGL 4.5 core, ...).
  explicit WindowContext(const WindowOptions& options);
  ~WindowContext() override;

  RenderTarget target() override;  // the back buffer (framebuffer 0) at its current size
  void present() override;         // glfwSwapBuffers
  void make_current() override;
  std::string description() const override;

  bool should_close() const;
  void poll_events();
  GLFWwindow* glfw_window() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace deixis::render
