// The front end on a runtime without XR_MNDX_egl_enable (issue 25, item 3): the test runtime with
// that extension hidden, so `deixis xr`'s context is a hidden GLFW window (GLX on a private Xvfb)
// and its session the Xlib binding. Through Debian's loader with core validation (which, unlike
// for the EGL binding, knows the Xlib one): every frame submitted with both views rendered by the
// real renderer into the runtime's textures (a captured frame is the renderer's picture, not
// blank), nothing refused, no validation error. With EGL offered the same front end stays on EGL;
// and a GLX session asked for with only an EGL context current says what it needs.

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/deixis_child.h"
#include "core/error.h"
#include "render/headless_context.h"
#include "render/renderer.h"
#include "tests/render/xvfb_server.h"
#include "tests/xr/xr_fixture.h"
#include "xr/frame_loop.h"
#include "xr/gl_context.h"
#include "xr/gl_session.h"
#include "xr/input.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

namespace deixis::xr {
namespace {

// Renders every view with the real renderer (an empty room: the sky and the floor).
class RenderingSink final : public FrameSink {
 public:
  explicit RenderingSink(render::Renderer& renderer) : renderer_(renderer) {}
  void on_frame(const FrameInfo&, const TrackingFrame&) override {}
  void render_view(std::uint32_t, const render::Camera& camera,
                   const render::RenderTarget& target) override {
    render::SceneView scene;
    scene.camera = camera;
    renderer_.render(scene, target);
    ++rendered;
  }
  int rendered = 0;

 private:
  render::Renderer& renderer_;
};

struct Ran {
  FrameLoopResult loop;
  bool egl = false;
  int rendered = 0;
};

// A whole session in the context the instance's binding takes (xr/gl_context.h).
Ran run_front_end() {
  Instance instance(InstanceOptions{});
  const std::unique_ptr<render::Context> context = make_gl_context(instance);
  render::Renderer renderer;
  RenderingSink sink(renderer);
  GlSession session(instance);
  Swapchains swapchains(instance, session);
  Input input(instance, session);
  FrameLoop loop(instance, session, swapchains, input);
  Ran ran;
  ran.loop = loop.run({}, sink);
  ran.egl = instance.features().egl;
  ran.rendered = sink.rendered;
  return ran;
}

class GlxSession : public XrRuntimeTest {
 protected:
  GlxSession() : XrRuntimeTest("deixis_xr_glx_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    write_script(R"({"display_hz": 90, "frames": 20, "capture_frames": [10], "keys": [{"t": 0,
      "head": {"position": [0, 1.6, 0], "orientation": [0, 0, 0, 1]}, "gaze": [0, -0.3, -1]}]})");
  }
};

TEST_F(GlxSession, WithoutEglTheFrontEndRendersThroughGlx) {
  render::testing::XvfbServer x;
  if (x.missing()) {
    GTEST_SKIP() << x.error();
  }
  ASSERT_TRUE(x.ready()) << x.error();
  setenv("DEIXIS_XR_HIDE_EXTENSIONS", "XR_MNDX_egl_enable", 1);
  const Ran ran = run_front_end();
  EXPECT_FALSE(ran.egl);
  EXPECT_EQ(ran.loop.frames, 20u);
  EXPECT_FALSE(ran.loop.lost);
  const nlohmann::json rec = record();
  EXPECT_EQ(rec["graphics"], "xlib");
  EXPECT_EQ(rec["refusals"].size(), 0u) << rec["refusals"].dump();
  std::uint64_t views = 0;
  for (const auto& f : rec["frames"]) {
    views += f["projection_views"].get<std::uint64_t>();
  }
  EXPECT_EQ(views, ran.loop.rendered_views);
  EXPECT_EQ(static_cast<std::uint64_t>(ran.rendered), ran.loop.rendered_views);
  EXPECT_GE(views, 2u * 18u);  // all but the frames before the session was VISIBLE
  // Frame 10 as the runtime read it back from its textures: the renderer's opaque picture.
  const auto& images = rec["frames"][10]["layer_list"][0]["images"];
  ASSERT_EQ(images.size(), 2u) << rec["frames"][10].dump();
  for (const auto& image : images) {
    EXPECT_EQ(image["opaque"].get<std::uint64_t>(), 512u * 512u) << image;
    std::ifstream pam(image["file"].get<std::string>(), std::ios::binary);
    std::stringstream read;
    read << pam.rdbuf();
    const std::string bytes = read.str();
    const std::size_t header = bytes.find("ENDHDR\n");
    ASSERT_NE(header, std::string::npos);
    std::size_t lit = 0;  // pixels with any colour: the sky and floor, not a cleared texture
    for (std::size_t i = header + 7; i + 3 < bytes.size(); i += 4) {
      lit += (bytes[i] | bytes[i + 1] | bytes[i + 2]) != 0 ? 1 : 0;
    }
    EXPECT_GT(lit, 512u * 512u / 2) << image;
  }
  EXPECT_EQ(validation_errors(), "");
}

// `deixis xr` itself on a runtime without EGL: its context is the hidden GLX window's (chosen by
// xr::make_gl_context), the session runs to its end and both views are rendered.
TEST_F(GlxSession, DeixisXrRendersThroughGlxWithoutEgl) {
  render::testing::XvfbServer x;
  if (x.missing()) {
    GTEST_SKIP() << x.error();
  }
  ASSERT_TRUE(x.ready()) << x.error();
  setenv("DEIXIS_XR_HIDE_EXTENSIONS", "XR_MNDX_egl_enable", 1);
  app::Deixis xr(std::vector<std::string>{"xr"});
  ASSERT_EQ(xr.wait(), 0) << xr.out() << xr.err();
  EXPECT_EQ(record()["graphics"], "xlib");
  const std::size_t at = xr.out().find("views rendered ");
  ASSERT_NE(at, std::string::npos) << xr.out();
  EXPECT_GE(std::atoi(xr.out().c_str() + at + 15), 2 * 18) << xr.out();
  EXPECT_EQ(validation_errors(), "");
}

// Debian 12's validation layer refuses the EGL binding (decisions.md 43): without it here.
TEST_F(GlxSession, WithEglOfferedTheFrontEndStaysOnEgl) {
  unsetenv("XR_ENABLE_API_LAYERS");
  const Ran ran = run_front_end();
  EXPECT_TRUE(ran.egl);
  EXPECT_EQ(ran.loop.frames, 20u);
  EXPECT_EQ(record()["graphics"], "egl");
}

TEST_F(GlxSession, AGlxSessionNeedsAGlxContext) {
  setenv("DEIXIS_XR_HIDE_EXTENSIONS", "XR_MNDX_egl_enable", 1);
  Instance instance(InstanceOptions{});
  render::HeadlessContext egl(16, 16);  // current, but not what the Xlib binding takes
  try {
    GlSession session(instance);
    ADD_FAILURE() << "a session without a GLX context";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Xlib/GLX"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis::xr
