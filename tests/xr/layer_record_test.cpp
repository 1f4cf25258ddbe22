// What the test runtime keeps of the layers an application submits (issue 25: "the recorded
// frames keep each layer's alpha and layer flags"): an OpenGL session (the renderer's EGL context,
// the front end's instance, session and swapchains) submits in ALPHA_BLEND a projection layer with
// BLEND_TEXTURE_SOURCE_ALPHA | UNPREMULTIPLIED_ALPHA whose views are transparent but for an opaque
// square, and a half-transparent quad layer; the record names the flags and counts the captured
// views' alpha pixel by pixel. Layers the spec forbids are refused. (Without the validation layer:
// Debian 12's refuses the EGL binding, decisions.md 43.)

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/gl.h"  // before OpenXR's platform header: the GL types
#include "render/headless_context.h"
#include "tests/xr/xr_calls.h"
#include "tests/xr/xr_fixture.h"
#include "xr/gl_session.h"
#include "xr/instance.h"
#include "xr/swapchains.h"

#define XR_USE_GRAPHICS_API_OPENGL  // XrSwapchainImageOpenGLKHR
#include <openxr/openxr_platform.h>

namespace deixis::xr {
namespace {

constexpr int kSquare = 100;  // the opaque square in each view, pixels
constexpr int kQuad = 64;     // the quad layer's image, pixels

class LayerRecord : public XrRuntimeTest {
 protected:
  LayerRecord() : XrRuntimeTest("deixis_xr_layers_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    unsetenv("XR_ENABLE_API_LAYERS");
    write_script(R"({"display_hz": 90, "blend_modes": ["ALPHA_BLEND", "OPAQUE"],
      "capture_frames": [3], "keys": [{"t": 0}]})");
  }

  // The quad's swapchain: one RGBA8 image set, a framebuffer per image.
  void make_quad(const GlSession& session) {
    auto ci = make<XrSwapchainCreateInfo>(XR_TYPE_SWAPCHAIN_CREATE_INFO);
    ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT;
    ci.format = GL_RGBA8;
    ci.sampleCount = ci.faceCount = ci.arraySize = ci.mipCount = 1;
    ci.width = ci.height = kQuad;
    XR_OK(xrCreateSwapchain(session.handle(), &ci, &quad_));
    uint32_t n = 0;
    XR_OK(xrEnumerateSwapchainImages(quad_, 0, &n, nullptr));
    std::vector<XrSwapchainImageOpenGLKHR> images(
        n, make<XrSwapchainImageOpenGLKHR>(XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR));
    XR_OK(xrEnumerateSwapchainImages(quad_, n, &n,
                                     reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())));
    quad_fbos_.assign(n, 0);
    glGenFramebuffers(static_cast<GLsizei>(n), quad_fbos_.data());
    for (uint32_t i = 0; i < n; ++i) {
      glBindFramebuffer(GL_FRAMEBUFFER, quad_fbos_[i]);
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, images[i].image,
                             0);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }

  // Transparent black with an opaque red square at the bottom left.
  static void draw_view(const render::RenderTarget& target) {
    glBindFramebuffer(GL_FRAMEBUFFER, target.framebuffer);
    glViewport(0, 0, target.width, target.height);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, kSquare, kSquare);
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
  }

  void draw_quad() {
    uint32_t i = 0;
    auto ai = make<XrSwapchainImageAcquireInfo>(XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO);
    XR_OK(xrAcquireSwapchainImage(quad_, &ai, &i));
    auto wi = make<XrSwapchainImageWaitInfo>(XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO);
    wi.timeout = XR_INFINITE_DURATION;
    XR_OK(xrWaitSwapchainImage(quad_, &wi));
    glBindFramebuffer(GL_FRAMEBUFFER, quad_fbos_[i]);
    glClearColor(0, 1, 0, 0.5f);
    glClear(GL_COLOR_BUFFER_BIT);
    glFinish();
    auto ri = make<XrSwapchainImageReleaseInfo>(XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO);
    XR_OK(xrReleaseSwapchainImage(quad_, &ri));
  }

  void run_frames();

  XrSwapchain quad_ = XR_NULL_HANDLE;
  std::vector<GLuint> quad_fbos_;
};

// Six frames, each a projection and a quad layer in ALPHA_BLEND; on the fifth, three layers the
// spec forbids first. Returns when the instance is gone (and the record written).
void LayerRecord::run_frames() {
  render::HeadlessContext context(16, 16);
  Instance instance(InstanceOptions{});
  GlSession session(instance);
  Swapchains swapchains(instance, session);
  make_quad(session);
  const XrSession s = session.handle();
  int ended = 0;
  bool refusals_checked = false;
  for (int guard = 0; guard < 100 && ended < 6; ++guard) {
    auto event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    while (xrPollEvent(instance.handle(), &event) == XR_SUCCESS) {
      if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED &&
          reinterpret_cast<const XrEventDataSessionStateChanged&>(event).state ==
              XR_SESSION_STATE_READY) {
        auto bi = make<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
        bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
        XR_OK(xrBeginSession(s, &bi));
      }
      event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    }
    auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
    auto fw = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
    XR_OK(xrWaitFrame(s, &fw, &fs));
    auto fb = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    XR_OK(xrBeginFrame(s, &fb));
    auto li = make<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = fs.predictedDisplayTime;
    li.space = session.stage();
    auto vs = make<XrViewState>(XR_TYPE_VIEW_STATE);
    XrView views[2] = {make<XrView>(XR_TYPE_VIEW), make<XrView>(XR_TYPE_VIEW)};
    uint32_t count = 0;
    XR_OK(xrLocateViews(s, &li, &vs, 2, &count, views));
    XrCompositionLayerProjectionView pv[2];
    for (uint32_t v = 0; v < 2; ++v) {
      draw_view(swapchains.acquire(v));
      glFinish();
      swapchains.release(v);
      pv[v] = make<XrCompositionLayerProjectionView>(XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW);
      pv[v].pose = views[v].pose;
      pv[v].fov = views[v].fov;
      pv[v].subImage = swapchains.sub_image(v);
    }
    draw_quad();
    auto projection = make<XrCompositionLayerProjection>(XR_TYPE_COMPOSITION_LAYER_PROJECTION);
    projection.layerFlags = XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT |
                            XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT;
    projection.space = session.stage();
    projection.viewCount = 2;
    projection.views = pv;
    auto quad = make<XrCompositionLayerQuad>(XR_TYPE_COMPOSITION_LAYER_QUAD);
    quad.layerFlags = XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
    quad.space = session.view();
    quad.eyeVisibility = XR_EYE_VISIBILITY_BOTH;
    quad.subImage = {quad_, {{0, 0}, {kQuad, kQuad}}, 0};
    quad.pose = {{0, 0, 0, 1}, {0, 0, -1}};
    quad.size = {0.3f, 0.3f};
    const XrCompositionLayerBaseHeader* layers[] = {
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&projection),
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&quad)};
    auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    ei.displayTime = fs.predictedDisplayTime;
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND;
    ei.layerCount = 2;
    ei.layers = layers;
    if (ended == 4 && !refusals_checked) {
      // What the spec forbids: an unknown flag, a rectangle beyond the image; then ADDITIVE,
      // which this headset does not offer.
      quad.layerFlags = 1u << 10;
      EXPECT_EQ(xrEndFrame(s, &ei), XR_ERROR_VALIDATION_FAILURE);
      quad.layerFlags = XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
      quad.subImage.imageRect.extent.width = kQuad + 1;
      EXPECT_EQ(xrEndFrame(s, &ei), XR_ERROR_SWAPCHAIN_RECT_INVALID);
      quad.subImage.imageRect.extent.width = kQuad;
      ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
      EXPECT_EQ(xrEndFrame(s, &ei), XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
      ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND;
      refusals_checked = true;
    }
    XR_OK(xrEndFrame(s, &ei));
    ++ended;
  }
  EXPECT_EQ(ended, 6);
  glDeleteFramebuffers(static_cast<GLsizei>(quad_fbos_.size()), quad_fbos_.data());
  xrDestroySwapchain(quad_);
}

TEST_F(LayerRecord, KeepsEachLayersFlagsAndAlpha) {
  run_frames();
  const nlohmann::json rec = record();
  ASSERT_EQ(rec["frames"].size(), 6u);
  for (const auto& f : rec["frames"]) {
    EXPECT_EQ(f["blend_mode"], "ALPHA_BLEND");
    ASSERT_EQ(f["layer_list"].size(), 2u) << f.dump();
    EXPECT_EQ(f["layer_list"][0]["type"], "projection");
    EXPECT_EQ(f["layer_list"][0]["flags"],
              nlohmann::json::array({"BLEND_TEXTURE_SOURCE_ALPHA", "UNPREMULTIPLIED_ALPHA"}));
    EXPECT_EQ(f["layer_list"][1]["type"], "quad");
    EXPECT_EQ(f["layer_list"][1]["flags"], nlohmann::json::array({"BLEND_TEXTURE_SOURCE_ALPHA"}));
  }
  // Frame 3's views: the square opaque, the rest transparent; the quad half transparent.
  const auto& captured = rec["frames"][3]["layer_list"];
  ASSERT_EQ(captured[0]["images"].size(), 2u) << captured.dump();
  for (const auto& image : captured[0]["images"]) {
    const std::uint64_t all =
        image["width"].get<std::uint64_t>() * image["height"].get<std::uint64_t>();
    EXPECT_EQ(image["opaque"].get<std::uint64_t>(), static_cast<std::uint64_t>(kSquare * kSquare));
    EXPECT_EQ(image["transparent"].get<std::uint64_t>(), all - kSquare * kSquare);
    EXPECT_EQ(image["partial"].get<std::uint64_t>(), 0u);
  }
  ASSERT_EQ(captured[1]["images"].size(), 1u);
  EXPECT_EQ(captured[1]["images"][0]["partial"].get<std::uint64_t>(),
            static_cast<std::uint64_t>(kQuad * kQuad));
  std::vector<std::string> refused;
  for (const auto& r : rec["refusals"]) {
    refused.push_back(r["result"].get<std::string>());
  }
  EXPECT_EQ(refused, (std::vector<std::string>{"XR_ERROR_VALIDATION_FAILURE",
                                               "XR_ERROR_SWAPCHAIN_RECT_INVALID",
                                               "XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED"}));
}

}  // namespace
}  // namespace deixis::xr
