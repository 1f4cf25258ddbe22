#include "render/window_context.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/error.h"
#include "render/gl.h"

namespace deixis::render {
namespace {

std::string glfw_reason() {
  const char* description = nullptr;
  const int code = glfwGetError(&description);
  if (code == GLFW_NO_ERROR || description == nullptr) {
    return "no reason given";
  }
  return description;
}

}  // namespace

WindowContext::WindowContext(const WindowOptions& options) {
  if (glfwInit() != GLFW_TRUE) {  // initialises GLFW once; later calls return at once
    throw Error("window: GLFW could not start: " + glfw_reason() +
                " (no display? use the headless context, or run under xvfb-run)");
  }
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  window_ =
      glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    const std::string reason = glfw_reason();
    throw Error("window: no " + std::to_string(options.width) + " x " +
                std::to_string(options.height) + " window with OpenGL 4.5 core: " + reason);
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options.vsync ? 1 : 0);
  try {
    require_gl_version(4, 5, "window");
  } catch (...) {
    glfwDestroyWindow(window_);
    throw;
  }
}

WindowContext::~WindowContext() {
  // No glfwTerminate: GLFW stays initialised for the process (header comment).
  glfwDestroyWindow(window_);
}

RenderTarget WindowContext::target() {
  int width = 0;
  int height = 0;
  glfwGetFramebufferSize(window_, &width, &height);
  return {0, width, height};
}

void WindowContext::present() {
  glfwSwapBuffers(window_);
}

void WindowContext::make_current() {
  glfwMakeContextCurrent(window_);
}

std::string WindowContext::description() const {
  return "GLFW window: " + gl_description();
}

bool WindowContext::should_close() const {
  return glfwWindowShouldClose(window_) == GLFW_TRUE;
}

void WindowContext::poll_events() {
  glfwPollEvents();
}

}  // namespace deixis::render
