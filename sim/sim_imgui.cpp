#include "sim/sim_imgui.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include "core/error.h"

namespace deixis::sim {

ImGuiLayer::ImGuiLayer(GLFWwindow* window) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  if (!ImGui_ImplGlfw_InitForOpenGL(window, true)) {
    ImGui::DestroyContext();
    throw Error("sim: Dear ImGui's GLFW backend could not start");
  }
  if (!ImGui_ImplOpenGL3_Init("#version 450 core")) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    throw Error("sim: Dear ImGui's OpenGL 3 backend could not start");
  }
}

ImGuiLayer::~ImGuiLayer() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void ImGuiLayer::begin_frame(const FrameInput* scripted) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  if (scripted != nullptr) {
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(scripted->pointer.x(), scripted->pointer.y());
    for (std::size_t b = 0; b < kButtons; ++b) {
      // A press and its release within one frame still reach the UI as a click.
      io.MouseDown[b] = scripted->down[b] || scripted->pressed[b];
    }
    io.KeyShift = scripted->shift;
    // Typed as the GLFW backend's character callback types a person's keys.
    for (const char c : scripted->text) {
      io.AddInputCharacter(static_cast<unsigned int>(c));
    }
  }
  ImGui::NewFrame();
}

void ImGuiLayer::render() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool ImGuiLayer::wants_mouse() const {
  return ImGui::GetIO().WantCaptureMouse;
}

bool ImGuiLayer::wants_keyboard() const {
  return ImGui::GetIO().WantCaptureKeyboard;
}

}  // namespace deixis::sim
