// A headless smoke test of the simulator's panel: Dear ImGui frames built by draw_panel and
// drawn with Debian's OpenGL 3 backend into an EGL surfaceless context (no window, no display).
// Every widget is there and drawn, the plots show what the rings hold, and clicks on the
// buttons come back as the panel's actions (not when the user is scripted). The network section
// is a form (join or host, the address or port, the passphrase shown as asterisks, Start) until
// a session runs, then the session's state with Leave; typed text reaches the form's fields.

#include <gtest/gtest.h>

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_internal.h>  // FindWindowByName: whether a tooltip was drawn

#include <string>

#include "render/headless_context.h"
#include "render/image.h"
#include "sim/sim_panel.h"

namespace deixis::sim {
namespace {

constexpr int kWidth = 1280;
constexpr int kHeight = 260;

bool magenta(std::array<std::uint8_t, 3> p) {
  return p[0] > 240 && p[1] < 15 && p[2] > 240;
}

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

  // The centre of the widget `label` as last drawn.
  ImVec2 centre(std::string_view label) const {
    const PanelWidgets::Item* item = widgets_.find(label);
    EXPECT_NE(item, nullptr) << label;
    if (item == nullptr) {
      return ImVec2(-1, -1);
    }
    return ImVec2(0.5f * (item->x0 + item->x1), 0.5f * (item->y0 + item->y1));
  }

  // Clicks the widget `label` (press in one frame, release in the next) and returns the actions
  // of the release.
  PanelActions click(std::string_view label) {
    if (widgets_.find(label) == nullptr) {
      ADD_FAILURE() << "no widget " << label;
      return {};
    }
    const ImVec2 centre = this->centre(label);
    frame(centre, false);
    PanelActions pressed = frame(centre, true);
    PanelActions released = frame(centre, false);
    EXPECT_FALSE(pressed.explain);  // an ImGui button fires on release
    return released;
  }

  // Clicks the field `label` and types `text` into it, as the GLFW backend types a person's keys.
  void type_into(std::string_view label, std::string_view text) {
    click(label);
    for (const char c : text) {
      ImGui::GetIO().AddInputCharacter(static_cast<unsigned int>(c));
    }
    frame(centre(label), false);
  }

  // The pixels of the widget `label` in the last frame, row by row.
  std::vector<std::array<std::uint8_t, 3>> pixels_of(std::string_view label) const {
    std::vector<std::array<std::uint8_t, 3>> out;
    const PanelWidgets::Item* item = widgets_.find(label);
    if (item == nullptr) {
      ADD_FAILURE() << "no widget " << label;
      return out;
    }
    for (int y = static_cast<int>(item->y0); y < static_cast<int>(item->y1); ++y) {
      for (int x = static_cast<int>(item->x0); x < static_cast<int>(item->x1); ++x) {
        out.push_back(image_.pixel(x, y));
      }
    }
    return out;
  }

  // Each of `labels` was drawn in the last frame, inside the panel and covered by it.
  void expect_drawn(std::initializer_list<const char*> labels) const {
    for (const char* label : labels) {
      SCOPED_TRACE(label);
      const PanelWidgets::Item* item = widgets_.find(label);
      if (item == nullptr) {
        ADD_FAILURE() << "not drawn";
        continue;
      }
      EXPECT_GT(item->x1 - item->x0, 3.0f);
      EXPECT_GT(item->y1 - item->y0, 3.0f);
      EXPECT_GE(item->x0, 0.0f);
      EXPECT_LE(item->x1, static_cast<float>(kWidth));
      EXPECT_LE(item->y1, static_cast<float>(kHeight));
      EXPECT_EQ(count(*item, magenta), 0);  // the panel covers it
    }
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

bool bright(std::array<std::uint8_t, 3> p) {
  return p[0] > 140 && p[1] > 140 && p[2] > 140;
}

TEST_F(SimPanelTest, EveryWidgetIsDrawnInsideThePanel) {
  frame();  // ImGui lays a window out in its first frame and draws it from the second
  frame();
  expect_drawn({"gaze",          "deictic",
                "idle",          "head weight",
                "hand weight",   "Look at partner (P)",
                "Explain (E)",   "Rest (R)",
                "object",        "Point",
                "Touch",         "Put B's objects back",
                "status",        "translation timing",
                "render timing", "frame",
                "network",       "Join",
                "Host",          "join address",
                "passphrase",    "Start",
                "avatar",        "avatar path",
                "Load avatar"});
  // Text and plot lines are drawn, not just boxes: bright pixels in the button and the plot.
  EXPECT_GT(count(*widgets_.find("Explain (E)"), bright), 20);
  EXPECT_GT(count(*widgets_.find("deictic"), bright), 20);
  // An empty ring plots nothing but its frame and value.
  EXPECT_LT(count(*widgets_.find("gaze"), bright), count(*widgets_.find("deictic"), bright));
}

bool red(std::array<std::uint8_t, 3> p) {
  return p[0] > 200 && p[1] < 140;
}

TEST_F(SimPanelTest, TheNetworkSectionIsAFormUntilASessionRuns) {
  // No session yet: the form, nothing of a session.
  frame();
  frame();
  expect_drawn({"Join", "Host", "join address", "room", "passphrase", "Start"});
  EXPECT_EQ(widgets_.find("network state"), nullptr);
  EXPECT_EQ(widgets_.find("Leave"), nullptr);
  EXPECT_TRUE(click("Start").start_network);

  // Running: role, address, counts and the state, Leave; no form.
  const PanelNetwork running{"join", "127.0.0.1", 7350,  true, "B", 120,
                             118,    "streaming", false, true, "",  {}};
  status_.network = &running;
  frame();
  frame();
  expect_drawn({"network", "network counts", "network state", "Leave"});
  EXPECT_EQ(widgets_.find("Start"), nullptr);
  EXPECT_EQ(widgets_.find("passphrase"), nullptr);
  EXPECT_EQ(count(*widgets_.find("network state"), red), 0);
  EXPECT_TRUE(click("Leave").leave_network);

  // In a room: its name and who is here, live or not, instead of one site's counts; Leave.
  const std::array<site::LivePerson, 2> people{site::LivePerson{"B", true, 90, 88},
                                               site::LivePerson{"C", false, 12, 10}};
  PanelNetwork room = running;
  room.role = "room";
  room.room = "meeting";
  room.state = "in the room";
  room.people = people;
  status_.network = &room;
  frame();
  frame();
  // Each person's link, as the headset's presence panel says it (site/link_health.h).
  expect_drawn({"network", "network counts", "person link", "network state", "Leave"});
  EXPECT_EQ(widgets_.find("Start"), nullptr);
  EXPECT_TRUE(click("Leave").leave_network);

  // Ended by a failure: the form again, to try again, and the error under it in red.
  const PanelNetwork failed{
      "join", "127.0.0.1", 7350, true, "B", 0, 0, "the host refused this site: wrong passphrase",
      true,   false,       "",   {}};
  status_.network = &failed;
  frame();
  frame();
  expect_drawn({"Join", "Host", "join address", "passphrase", "Start", "network state"});
  EXPECT_EQ(widgets_.find("Leave"), nullptr);
  EXPECT_GT(count(*widgets_.find("network state"), red), 20);
  EXPECT_EQ(count(*widgets_.find("join address"), red), 0);
  EXPECT_TRUE(click("Start").start_network);

  // A problem the last Start found in the form, in red too.
  status_.form_problem = "Join: localhost: the panel takes a numeric address";
  frame();
  EXPECT_GT(count(*widgets_.find("network problem"), red), 20);
}

TEST_F(SimPanelTest, TypedTextFillsTheFormAndThePassphraseStaysHidden) {
  frame();
  frame();
  // A click selects the whole field, so what is typed replaces the default.
  std::snprintf(edits_.network.endpoint.data(), edits_.network.endpoint.size(), "127.0.0.1:7350");
  type_into("join address", "10.0.0.2:7400");
  EXPECT_STREQ(edits_.network.endpoint.data(), "10.0.0.2:7400");
  type_into("passphrase", "blue whale");
  EXPECT_STREQ(edits_.network.passphrase.data(), "blue whale");

  // Host: the port field instead of the address.
  click("Host");
  frame();
  EXPECT_TRUE(edits_.network.host);
  EXPECT_EQ(widgets_.find("join address"), nullptr);
  type_into("host port", "0");
  EXPECT_STREQ(edits_.network.port.data(), "0");
  click("Join");
  frame();
  EXPECT_FALSE(edits_.network.host);

  // Two passphrases of one length draw the same asterisks; two addresses of one length (the
  // control: a field in clear) do not look alike.
  const auto drawn = [this](char* field, std::size_t size, const char* text, const char* label) {
    std::snprintf(field, size, "%s", text);
    frame();
    return pixels_of(label);
  };
  NetworkForm& f = edits_.network;
  EXPECT_EQ(drawn(f.passphrase.data(), f.passphrase.size(), "iiiiiiii", "passphrase"),
            drawn(f.passphrase.data(), f.passphrase.size(), "WWWWWWWW", "passphrase"));
  EXPECT_NE(drawn(f.endpoint.data(), f.endpoint.size(), "iiiiiiii", "join address"),
            drawn(f.endpoint.data(), f.endpoint.size(), "WWWWWWWW", "join address"));
}

TEST_F(SimPanelTest, StartIsOffInAFixedStepRunAndSaysWhy) {
  status_.start_disabled = "--fixed-step: a session runs on the wall clock";
  frame();
  frame();
  EXPECT_FALSE(click("Start").start_network);
  const auto tooltip_shown = [] {
    const ImGuiWindow* tip = ImGui::FindWindowByName("##Tooltip_00");
    return tip != nullptr && tip->Active;
  };
  frame(centre("Start"));
  EXPECT_TRUE(tooltip_shown());
  frame();
  EXPECT_FALSE(tooltip_shown());
  status_.start_disabled = {};
  frame(centre("Start"));
  EXPECT_FALSE(tooltip_shown());  // nothing to explain when it is on
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
}  // namespace deixis::sim
