// A headless smoke test of the simulator's panel: Dear ImGui frames built by draw_panel and
// drawn with Debian's OpenGL 3 backend into an EGL surfaceless context (no window, no display).
// Every widget is there and drawn, the plots show what the rings hold, and clicks on the
// buttons come back as the panel's actions (not when the user is scripted).

#include <gtest/gtest.h>

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <string>

#include "app/sim_panel.h"
#include "render/headless_context.h"
#include "render/image.h"

namespace deixis::app {
namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 260;

class SimPanelTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context_.emplace(kWidth, kHeight);
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(kWidth, kHeight);
    ImGui::StyleColorsDark();
    ASSERT_TRUE(ImGui_ImplOpenGL3_Init("#version 450 core"));
    for (int i = 0; i < 200; ++i) {  // a ramp the plots must show
      const float v = static_cast<float>(i % 100) / 100.0f;
      history_.progression[1].push(v);
      history_.tick_ms.push(0.2f + 0.001f * static_cast<float>(i));
      history_.frame_ms.push(16.0f);
    }
    objects_ = {{1, "Jupiter", TargetKind::kSphere, Vec3(1, 1, -2), Vec3::Constant(0.4f)},
                {4, "Cube", TargetKind::kBox, Vec3(0, 1, -1), Vec3::Constant(0.1f)}};
    status_.history = &history_;
    status_.local_objects = objects_;
    status_.status = "Pointing at Jupiter";
    status_.avatar = "assets/avatars/default.glb";
  }
  void TearDown() override {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext();
  }

  // One UI frame with the mouse at `mouse` (button down or not), drawn and read back.
  PanelActions frame(ImVec2 mouse = ImVec2(-1, -1), bool down = false) {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 30.0f;
    io.MousePos = mouse;
    io.MouseDown[0] = down;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    const PanelActions actions =
        draw_panel(ViewRect{0, 0, kWidth, kHeight}, status_, edits_, &widgets_);
    ImGui::Render();
    const render::RenderTarget target = context_->target();
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    glViewport(0, 0, target.width, target.height);
    glClearColor(1.0f, 0.0f, 1.0f, 1.0f);  // magenta: whatever the panel does not cover
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    image_ = render::read_pixels(target);
    return actions;
  }

  // Clicks the widget `label` (press in one frame, release in the next) and returns the actions
  // of the release.
  PanelActions click(std::string_view label) {
    const PanelWidgets::Item* item = widgets_.find(label);
    EXPECT_NE(item, nullptr) << label;
    if (item == nullptr) {
      return {};
    }
    const ImVec2 centre(0.5f * (item->x0 + item->x1), 0.5f * (item->y0 + item->y1));
    frame(centre, false);
    PanelActions pressed = frame(centre, true);
    PanelActions released = frame(centre, false);
    EXPECT_FALSE(pressed.explain);  // an ImGui button fires on release
    return released;
  }

  int count(const PanelWidgets::Item& item, bool (*test)(std::array<std::uint8_t, 3>)) const {
    int n = 0;
    for (int y = static_cast<int>(item.y0); y < static_cast<int>(item.y1); ++y) {
      for (int x = static_cast<int>(item.x0); x < static_cast<int>(item.x1); ++x) {
        n += test(image_.pixel(x, y)) ? 1 : 0;
      }
    }
    return n;
  }

  std::optional<render::HeadlessContext> context_;
  SimHistory history_;
  std::vector<TargetObject> objects_;
  PanelStatus status_;
  PanelEdits edits_;
  PanelWidgets widgets_;
  render::Image image_;
};

bool magenta(std::array<std::uint8_t, 3> p) {
  return p[0] > 240 && p[1] < 15 && p[2] > 240;
}
bool bright(std::array<std::uint8_t, 3> p) {
  return p[0] > 140 && p[1] > 140 && p[2] > 140;
}

TEST_F(SimPanelTest, EveryWidgetIsDrawnInsideThePanel) {
  frame();  // ImGui lays a window out in its first frame and draws it from the second
  frame();
  for (const char* label : {"gaze",          "deictic",
                            "idle",          "head weight",
                            "hand weight",   "Look at partner (P)",
                            "Explain (E)",   "Rest (R)",
                            "object",        "Point",
                            "Touch",         "Put B's objects back",
                            "status",        "translation timing",
                            "render timing", "frame",
                            "network",       "avatar",
                            "avatar path",   "Load avatar"}) {
    SCOPED_TRACE(label);
    const PanelWidgets::Item* item = widgets_.find(label);
    ASSERT_NE(item, nullptr);
    EXPECT_GT(item->x1 - item->x0, 3.0f);
    EXPECT_GT(item->y1 - item->y0, 3.0f);
    EXPECT_GE(item->x0, 0.0f);
    EXPECT_LE(item->x1, static_cast<float>(kWidth));
    EXPECT_LE(item->y1, static_cast<float>(kHeight));
    EXPECT_EQ(count(*item, magenta), 0);  // the panel covers it
  }
  // Text and plot lines are drawn, not just boxes: bright pixels in the button and the plot.
  EXPECT_GT(count(*widgets_.find("Explain (E)"), bright), 20);
  EXPECT_GT(count(*widgets_.find("deictic"), bright), 20);
  // An empty ring plots nothing but its frame and value.
  EXPECT_LT(count(*widgets_.find("gaze"), bright), count(*widgets_.find("deictic"), bright));
}

TEST_F(SimPanelTest, TheNetworkSectionShowsTheSession) {
  // Local: one line. Networked: role, address, counts and the state, inside the panel; a
  // failure's text is drawn in red.
  frame();
  frame();
  EXPECT_EQ(widgets_.find("network state"), nullptr);
  const PanelNetwork joined{
      "join", "127.0.0.1", 7350, true, "B", 120, 118, "nobody came within 30 s", true};
  status_.network = &joined;
  frame();
  frame();
  for (const char* label : {"network", "network counts", "network state", "avatar path"}) {
    SCOPED_TRACE(label);
    const PanelWidgets::Item* item = widgets_.find(label);
    ASSERT_NE(item, nullptr);
    EXPECT_GT(item->x1 - item->x0, 3.0f);
    EXPECT_LE(item->y1, static_cast<float>(kHeight));
    EXPECT_EQ(count(*item, magenta), 0);
  }
  const auto red = [](std::array<std::uint8_t, 3> p) { return p[0] > 200 && p[1] < 140; };
  EXPECT_GT(count(*widgets_.find("network state"), red), 20);
  EXPECT_EQ(count(*widgets_.find("network counts"), red), 0);
}

TEST_F(SimPanelTest, ButtonsComeBackAsActions) {
  frame();
  frame();
  EXPECT_TRUE(click("Explain (E)").explain);
  EXPECT_TRUE(click("Rest (R)").rest);
  EXPECT_TRUE(click("Look at partner (P)").look_at_partner);
  EXPECT_EQ(click("Point").point, 1);
  edits_.selected = 4;
  EXPECT_EQ(click("Touch").touch, 4);
  EXPECT_TRUE(click("Put B's objects back").reset_objects);
  EXPECT_TRUE(click("Load avatar").load_avatar);
  const PanelActions nothing = frame();
  EXPECT_FALSE(nothing.explain || nothing.rest || nothing.load_avatar);
}

TEST_F(SimPanelTest, AScriptedUserTakesNoCommands) {
  status_.scripted_user = true;
  frame();
  frame();
  EXPECT_FALSE(click("Explain (E)").explain);
  EXPECT_EQ(click("Point").point, kNoTarget);
  EXPECT_TRUE(click("Put B's objects back").reset_objects);  // dragging still works
}

}  // namespace
}  // namespace deixis::app
