// The GLFW window context under a private Xvfb: a real window with an OpenGL 4.5 core context
// that the same renderer draws into, read back from the back buffer, and presented.

#include <gtest/gtest.h>

#include <cstdlib>

#include "core/error.h"
#include "render/renderer.h"
#include "render/window_context.h"
#include "render_fixtures.h"
#include "xvfb_server.h"

namespace deixis::render {
namespace {

using namespace deixis::render::testing;

// GLFW stays initialised, and connected to its X server, until the process exits
// (render/window_context.h), so the server must outlive every test of this process.
const XvfbServer& shared_xvfb() {
  static XvfbServer server;
  return server;
}

// First: GLFW is still uninitialised only before any window was opened in this process (ctest
// runs each test in a process of its own anyway).
TEST(WindowContextTest, NoDisplayIsAClearError) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  try {
    WindowContext window(WindowOptions{});
    FAIL() << "expected an error without a display";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("GLFW could not start"), std::string::npos) << message;
    EXPECT_NE(message.find("DISPLAY"), std::string::npos) << message;
  }
}

TEST(WindowContextTest, RendersIntoAWindowUnderXvfb) {
  const XvfbServer& xvfb = shared_xvfb();
  if (xvfb.missing()) {
    GTEST_SKIP() << xvfb.error();
  }
  ASSERT_TRUE(xvfb.ready()) << xvfb.error();
  WindowOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.title = "Deixis window test";
  WindowContext window(options);
  EXPECT_NE(window.description().find("GLFW window"), std::string::npos);
  const RenderTarget target = window.target();
  EXPECT_EQ(target.framebuffer, 0u);
  EXPECT_EQ(target.width, kWidth);
  EXPECT_EQ(target.height, kHeight);
  {
    Renderer renderer;
    TargetMap room;
    room.objects = {{4, "Lamp", TargetKind::kSphere, Vec3(0.5f, 1.2f, 0), Vec3::Constant(0.5f)}};
    renderer.set_targets(room);
    SceneView view;
    view.camera = front_camera();
    view.show_labels = false;
    for (int frame = 0; frame < 3; ++frame) {
      renderer.render(view, window.target());
      check_gl("window render");
      const Image image = read_pixels(window.target());
      const Rgb lamp = pixel_at(image, view.camera, room.objects[0].position);
      EXPECT_TRUE(same_hue(lamp, target_colour(4)))
          << int{lamp[0]} << " " << int{lamp[1]} << " " << int{lamp[2]};
      EXPECT_TRUE(near(image.pixel(5, 5), to_rgb(renderer.options().background), 2));
      window.present();
      window.poll_events();
    }
    EXPECT_FALSE(window.should_close());
    EXPECT_NE(window.glfw_window(), nullptr);
  }
  // A second window beside the first, and after it: GLFW is set up once per process.
  options.width = 160;
  options.height = 120;
  WindowContext second(options);
  EXPECT_EQ(second.target().width, 160);
  EXPECT_EQ(second.target().height, 120);
  Renderer renderer;
  SceneView view;
  view.camera = front_camera();
  renderer.render(view, second.target());
  EXPECT_TRUE(
      near(read_pixels(second.target()).pixel(3, 3), to_rgb(renderer.options().background), 2));
  window.make_current();
  EXPECT_EQ(window.target().width, kWidth);
}

}  // namespace
}  // namespace deixis::render
