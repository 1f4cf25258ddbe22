// The project's OpenXR test runtime through Debian's real loader (libopenxr_loader) with
// XR_APILAYER_LUNARG_core_validation enabled: a headless session driven by the session state
// machine runs its frame loop to the end; frames are submitted in order with the predicted
// display time; the runtime refuses out-of-order calls; the validation layer reports nothing.

#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/xr/xr_calls.h"
#include "tests/xr/xr_fixture.h"
#include "xr/session_state.h"

namespace deixis::xr {
namespace {

namespace fs = std::filesystem;

class TestRuntime : public XrRuntimeTest {
 protected:
  TestRuntime() : XrRuntimeTest("deixis_xr_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    write_script(R"({"display_hz": 90, "frames": 12, "keys": [
      {"t": 0, "head": {"position": [0, 1.6, 0]}},
      {"t": 1, "head": {"position": [0.1, 1.6, 0]}, "gaze": [0, -0.2, -1]}]})");
  }

  // xrCreateInstance with XR_MND_headless into instance_; the result, for tests that expect a
  // refusal.
  XrResult create_headless_instance() {
    const char* extensions[] = {"XR_MND_headless"};
    auto ci = make<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
    std::snprintf(ci.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "deixis-test");
    ci.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
    ci.enabledExtensionCount = 1;
    ci.enabledExtensionNames = extensions;
    return xrCreateInstance(&ci, &instance_);
  }

  void create_headless() {
    XR_OK(create_headless_instance());
    auto sg = make<XrSystemGetInfo>(XR_TYPE_SYSTEM_GET_INFO);
    sg.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XR_OK(xrGetSystem(instance_, &sg, &system_));
    auto sc = make<XrSessionCreateInfo>(XR_TYPE_SESSION_CREATE_INFO);
    sc.systemId = system_;
    XR_OK(xrCreateSession(instance_, &sc, &session_));
    auto rs = make<XrReferenceSpaceCreateInfo>(XR_TYPE_REFERENCE_SPACE_CREATE_INFO);
    rs.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_STAGE;
    rs.poseInReferenceSpace.orientation.w = 1.0f;
    XR_OK(xrCreateReferenceSpace(session_, &rs, &stage_));
  }

  void destroy() {
    if (session_ != XR_NULL_HANDLE) {
      xrDestroySpace(stage_);
      xrDestroySession(session_);
    }
    if (instance_ != XR_NULL_HANDLE) {
      EXPECT_EQ(xrDestroyInstance(instance_), XR_SUCCESS);
    }
    session_ = XR_NULL_HANDLE;
    instance_ = XR_NULL_HANDLE;
  }

  void TearDown() override { destroy(); }

  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace stage_ = XR_NULL_HANDLE;
};

TEST_F(TestRuntime, ScriptedHeadlessSessionRunsToExitingInOrderWithoutValidationErrors) {
  create_headless();
  SessionMachine m;
  int frames = 0;
  for (int guard = 0; guard < 1000 && !m.finished; ++guard) {
    auto event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    while (xrPollEvent(instance_, &event) == XR_SUCCESS) {
      if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
        const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
        const SessionStep step = on_event(
            m, {SessionEventKind::kStateChanged, static_cast<SessionState>(changed.state)});
        if (step.actions.begin_session) {
          auto bi = make<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
          bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
          XR_OK(xrBeginSession(session_, &bi));
        }
        if (step.actions.end_session) {
          XR_OK(xrEndSession(session_));
        }
        m = step.next;
      }
      event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    }
    if (!runs_frame_loop(m)) {
      continue;
    }
    auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
    auto wi = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
    XR_OK(xrWaitFrame(session_, &wi, &fs));
    auto bi = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    XR_OK(xrBeginFrame(session_, &bi));
    if (fs.shouldRender == XR_TRUE) {
      auto li = make<XrViewLocateInfo>(XR_TYPE_VIEW_LOCATE_INFO);
      li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
      li.displayTime = fs.predictedDisplayTime;
      li.space = stage_;
      auto vs = make<XrViewState>(XR_TYPE_VIEW_STATE);
      XrView views[2] = {make<XrView>(XR_TYPE_VIEW), make<XrView>(XR_TYPE_VIEW)};
      uint32_t count = 0;
      XR_OK(xrLocateViews(session_, &li, &vs, 2, &count, views));
      EXPECT_EQ(count, 2u);
      EXPECT_NEAR(views[1].pose.position.x - views[0].pose.position.x, 0.063f, 1e-4f);
      EXPECT_NEAR(views[0].pose.position.y, 1.6f, 1e-4f);
    }
    auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    ei.displayTime = fs.predictedDisplayTime;
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    XR_OK(xrEndFrame(session_, &ei));
    ++frames;
  }
  EXPECT_TRUE(m.finished);
  EXPECT_FALSE(m.lost);
  EXPECT_EQ(frames, 12);
  destroy();
  const nlohmann::json r = record();
  ASSERT_EQ(r["frames"].size(), 12u);
  long long previous = 0;
  for (std::size_t i = 0; i < r["frames"].size(); ++i) {
    const auto& f = r["frames"][i];
    EXPECT_EQ(f["index"].get<std::size_t>(), i);
    EXPECT_EQ(f["submitted_display_time"], f["predicted_display_time"]);
    EXPECT_GT(f["predicted_display_time"].get<long long>(), previous);
    previous = f["predicted_display_time"].get<long long>();
  }
  EXPECT_EQ(r["refusals"].size(), 0u) << r["refusals"].dump();
  const std::vector<std::string> states = r["states"];
  const std::vector<std::string> expected = {"IDLE",    "READY",   "SYNCHRONIZED", "VISIBLE",
                                             "FOCUSED", "VISIBLE", "SYNCHRONIZED", "STOPPING",
                                             "IDLE",    "EXITING"};
  EXPECT_EQ(states, expected);
  EXPECT_EQ(validation_errors(), "");
}

// A malformed script is refused at xrCreateInstance, its message naming the bad field.
TEST_F(TestRuntime, ABadScriptIsRefusedNamingTheField) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"realtime": "yes", "keys": [{"t": 0}]})", "realtime"},
      {R"({"display_hz": 0, "keys": [{"t": 0}]})", "display_hz"},
      {R"({"frames": -1, "keys": [{"t": 0}]})", "frames"},
      {R"({"display_hz": 30})", "keys"},
  };
  for (const auto& [script, field] : cases) {
    write_script(script);
    // The runtime says why on stderr.
    const auto [r, said] =
        with_stderr(dir_ / "stderr.txt", [this] { return create_headless_instance(); });
    EXPECT_EQ(r, XR_ERROR_INITIALIZATION_FAILED) << script;
    if (XR_SUCCEEDED(r)) {
      xrDestroyInstance(instance_);
    }
    instance_ = XR_NULL_HANDLE;
    EXPECT_NE(said.find("DEIXIS_XR_SCRIPT"), std::string::npos) << said;
    EXPECT_NE(said.find(field), std::string::npos) << said;
  }
}

TEST_F(TestRuntime, RefusesOutOfOrderCalls) {
  create_headless();
  auto begin = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  auto wait = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
  // Not begun yet.
  EXPECT_EQ(xrWaitFrame(session_, &wait, &fs), XR_ERROR_SESSION_NOT_RUNNING);
  XR_OK(xrEndSession(session_) == XR_ERROR_SESSION_NOT_RUNNING ? XR_SUCCESS
                                                               : XR_ERROR_RUNTIME_FAILURE);
  auto event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
  while (xrPollEvent(instance_, &event) == XR_SUCCESS) {
    event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
  }
  auto bi = make<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
  bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  XR_OK(xrBeginSession(session_, &bi));
  EXPECT_EQ(xrBeginSession(session_, &bi), XR_ERROR_SESSION_RUNNING);
  EXPECT_EQ(xrBeginFrame(session_, &begin), XR_ERROR_CALL_ORDER_INVALID);  // no xrWaitFrame
  auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  ei.displayTime = 1;
  EXPECT_EQ(xrEndFrame(session_, &ei), XR_ERROR_CALL_ORDER_INVALID);  // no xrBeginFrame
  XR_OK(xrWaitFrame(session_, &wait, &fs));
  XR_OK(xrBeginFrame(session_, &begin));
  ei.displayTime = fs.predictedDisplayTime + 1;
  EXPECT_EQ(xrEndFrame(session_, &ei), XR_ERROR_TIME_INVALID);  // not the predicted time
  ei.displayTime = fs.predictedDisplayTime;
  XR_OK(xrEndFrame(session_, &ei));
  EXPECT_EQ(xrEndSession(session_), XR_ERROR_SESSION_NOT_STOPPING);
  destroy();
  const nlohmann::json r = record();
  std::vector<std::string> refused;
  for (const auto& x : r["refusals"]) {
    refused.push_back(x["call"].get<std::string>() + ":" + x["result"].get<std::string>());
  }
  const std::vector<std::string> expected = {
      "xrWaitFrame:XR_ERROR_SESSION_NOT_RUNNING",  "xrEndSession:XR_ERROR_SESSION_NOT_RUNNING",
      "xrBeginSession:XR_ERROR_SESSION_RUNNING",   "xrBeginFrame:XR_ERROR_CALL_ORDER_INVALID",
      "xrEndFrame:XR_ERROR_CALL_ORDER_INVALID",    "xrEndFrame:XR_ERROR_TIME_INVALID",
      "xrEndSession:XR_ERROR_SESSION_NOT_STOPPING"};
  EXPECT_EQ(refused, expected);
}

// The check above can fail: a structure of the wrong type is reported by the layer.
TEST_F(TestRuntime, ValidationLayerReportsAMisuse) {
  create_headless();
  auto wrong = make<XrSystemGetInfo>(XR_TYPE_SESSION_BEGIN_INFO);
  wrong.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  XrSystemId id = XR_NULL_SYSTEM_ID;
  EXPECT_EQ(xrGetSystem(instance_, &wrong, &id), XR_ERROR_VALIDATION_FAILURE);
  destroy();
  EXPECT_NE(validation_errors(), "");
}

}  // namespace
}  // namespace deixis::xr
