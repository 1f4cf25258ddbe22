// The test runtime's input as the OpenXR spec says it (issue 25), through Debian's loader with
// XR_APILAYER_LUNARG_core_validation, on a headless session: suggested bindings for every
// interaction profile of the spec and refusals of paths the spec does not define; scripted
// buttons, triggers and sticks in boolean, float and vector2 action states with
// changedSinceLastSync, lastChangeTime and isActive; the interaction profile the headset's
// script prefers, its event, the bound sources and their names; haptics recorded; the blend
// modes the script offers and xrEndFrame refusing another.

#include <openxr/openxr.h>
#include <openxr/openxr_reflection.h>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/xr/xr_calls.h"
#include "tests/xr/xr_fixture.h"

namespace deixis::xr {
namespace {

constexpr const char* kIndex = "/interaction_profiles/valve/index_controller";
constexpr const char* kSimple = "/interaction_profiles/khr/simple_controller";

// A headset with Index controllers first, then simple ones. The right hand presses a from 0.1 s
// to 0.4 s, squeezes the trigger from 0 at 0.2 s to 1 at 0.3 s and holds the thumbstick at
// (0.5, -1) from 0.2 s to 0.3 s.
constexpr const char* kScript = R"({"display_hz": 90, "frames": 60,
  "profiles": ["/interaction_profiles/valve/index_controller",
               "/interaction_profiles/khr/simple_controller"],
  "blend_modes": ["ALPHA_BLEND", "ADDITIVE"],
  "keys": [{"t": 0},
           {"t": 0.1, "input": {"right": {"a": true}}},
           {"t": 0.2, "input": {"right": {"a": true, "trigger": 0.0, "thumbstick": [0.5, -1]}}},
           {"t": 0.3, "input": {"right": {"a": true, "trigger": 1.0, "thumbstick": [0.5, -1]}}},
           {"t": 0.4, "input": {"right": {"trigger": 1.0}}}]})";

class RuntimeInput : public XrRuntimeTest {
 protected:
  RuntimeInput() : XrRuntimeTest("deixis_xr_input_") {}

  void SetUp() override {
    XrRuntimeTest::SetUp();
    write_script(kScript);
  }

  void TearDown() override { destroy(); }

  XrResult create_instance(bool eye_gaze) {
    std::vector<const char*> extensions = {"XR_MND_headless"};
    if (eye_gaze) {
      extensions.push_back("XR_EXT_eye_gaze_interaction");
    }
    auto ci = make<XrInstanceCreateInfo>(XR_TYPE_INSTANCE_CREATE_INFO);
    std::snprintf(ci.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "input-test");
    ci.applicationInfo.apiVersion = XR_CURRENT_API_VERSION;
    ci.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    ci.enabledExtensionNames = extensions.data();
    return xrCreateInstance(&ci, &instance_);
  }

  // Instance, system, headless session, STAGE, and the action set with one action per type.
  void create(bool eye_gaze = false) {
    XR_OK(create_instance(eye_gaze));
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
    auto si = make<XrActionSetCreateInfo>(XR_TYPE_ACTION_SET_CREATE_INFO);
    std::strcpy(si.actionSetName, "input");
    std::strcpy(si.localizedActionSetName, "Input");
    XR_OK(xrCreateActionSet(instance_, &si, &set_));
    hands_[0] = path("/user/hand/left");
    hands_[1] = path("/user/hand/right");
    for (auto [action, type, n] : {std::tuple{&press_, XR_ACTION_TYPE_BOOLEAN_INPUT, "press"},
                                   std::tuple{&squeeze_, XR_ACTION_TYPE_FLOAT_INPUT, "squeeze"},
                                   std::tuple{&stick_, XR_ACTION_TYPE_VECTOR2F_INPUT, "stick"},
                                   std::tuple{&grip_, XR_ACTION_TYPE_POSE_INPUT, "grip"},
                                   std::tuple{&buzz_, XR_ACTION_TYPE_VIBRATION_OUTPUT, "buzz"}}) {
      auto ai = make<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
      ai.actionType = type;
      std::strcpy(ai.actionName, n);
      std::strcpy(ai.localizedActionName, n);
      ai.countSubactionPaths = 2;
      ai.subactionPaths = hands_;
      XR_OK(xrCreateAction(set_, &ai, action));
    }
  }

  XrPath path(const char* s) {
    XrPath p = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(instance_, s, &p), XR_SUCCESS) << s;
    return p;
  }

  XrResult suggest(const char* profile, const std::vector<std::pair<XrAction, std::string>>& list) {
    std::vector<XrActionSuggestedBinding> bindings;
    for (const auto& [action, p] : list) {
      bindings.push_back({action, path(p.c_str())});
    }
    auto sb =
        make<XrInteractionProfileSuggestedBinding>(XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING);
    sb.interactionProfile = path(profile);
    sb.countSuggestedBindings = static_cast<uint32_t>(bindings.size());
    sb.suggestedBindings = bindings.data();
    return xrSuggestInteractionProfileBindings(instance_, &sb);
  }

  // Index and simple-controller bindings for both hands, then attach.
  void bind_and_attach() {
    std::vector<std::pair<XrAction, std::string>> index, simple;
    for (const std::string hand : {"/user/hand/left", "/user/hand/right"}) {
      index.insert(index.end(), {{press_, hand + "/input/a/click"},
                                 {squeeze_, hand + "/input/trigger/value"},
                                 {stick_, hand + "/input/thumbstick"},
                                 {grip_, hand + "/input/grip/pose"},
                                 {buzz_, hand + "/output/haptic"}});
      simple.insert(simple.end(), {{press_, hand + "/input/select/click"},
                                   {grip_, hand + "/input/grip/pose"},
                                   {buzz_, hand + "/output/haptic"}});
    }
    XR_OK(suggest(kIndex, index));
    XR_OK(suggest(kSimple, simple));
    auto ai = make<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
    ai.countActionSets = 1;
    ai.actionSets = &set_;
    XR_OK(xrAttachSessionActionSets(session_, &ai));
  }

  // Events: begins the session when READY, counts the interaction profile events.
  void poll() {
    auto event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    while (xrPollEvent(instance_, &event) == XR_SUCCESS) {
      if (event.type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED) {
        ++profile_events_;
      }
      if (event.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) {
        state_ = reinterpret_cast<const XrEventDataSessionStateChanged&>(event).state;
        if (state_ == XR_SESSION_STATE_READY) {
          auto bi = make<XrSessionBeginInfo>(XR_TYPE_SESSION_BEGIN_INFO);
          bi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
          EXPECT_EQ(xrBeginSession(session_, &bi), XR_SUCCESS);
        }
      }
      event = make<XrEventDataBuffer>(XR_TYPE_EVENT_DATA_BUFFER);
    }
  }

  // One frame: events, wait, begin, sync (its result in sync_), `between`, end in ADDITIVE.
  template <typename F>
  void frame(F&& between) {
    poll();
    auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
    auto wi = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
    XR_OK(xrWaitFrame(session_, &wi, &fs));
    auto bi = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
    XR_OK(xrBeginFrame(session_, &bi));
    if (first_time_ == 0) {
      first_time_ = fs.predictedDisplayTime;
    }
    time_ = fs.predictedDisplayTime;
    XrActiveActionSet active{set_, XR_NULL_PATH};
    auto sync = make<XrActionsSyncInfo>(XR_TYPE_ACTIONS_SYNC_INFO);
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    sync_ = xrSyncActions(session_, &sync);
    between();
    auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
    ei.displayTime = fs.predictedDisplayTime;
    ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ADDITIVE;
    XR_OK(xrEndFrame(session_, &ei));
  }

  double t() const { return static_cast<double>(time_ - first_time_) * 1e-9; }

  XrActionStateGetInfo get(XrAction action, XrPath subaction = XR_NULL_PATH) const {
    auto gi = make<XrActionStateGetInfo>(XR_TYPE_ACTION_STATE_GET_INFO);
    gi.action = action;
    gi.subactionPath = subaction;
    return gi;
  }

  void destroy() {
    if (instance_ != XR_NULL_HANDLE) {
      EXPECT_EQ(xrDestroyInstance(instance_), XR_SUCCESS);
    }
    instance_ = XR_NULL_HANDLE;
  }

  XrInstance instance_ = XR_NULL_HANDLE;
  XrSystemId system_ = XR_NULL_SYSTEM_ID;
  XrSession session_ = XR_NULL_HANDLE;
  XrSpace stage_ = XR_NULL_HANDLE;
  XrActionSet set_ = XR_NULL_HANDLE;
  XrAction press_ = XR_NULL_HANDLE, squeeze_ = XR_NULL_HANDLE, stick_ = XR_NULL_HANDLE,
           grip_ = XR_NULL_HANDLE, buzz_ = XR_NULL_HANDLE;
  XrPath hands_[2] = {XR_NULL_PATH, XR_NULL_PATH};
  XrSessionState state_ = XR_SESSION_STATE_UNKNOWN;
  int profile_events_ = 0;
  XrResult sync_ = XR_SUCCESS;
  XrTime first_time_ = 0, time_ = 0;
};

// Every core profile with paths of each kind it defines (hand-specific ones on their hand), and
// the eye gaze profile with its extension: all accepted. Paths a profile lacks are refused.
TEST_F(RuntimeInput, SuggestedBindingsFollowTheSpecsProfiles) {
  create(/*eye_gaze=*/true);
  const std::vector<std::pair<const char*, std::vector<std::pair<XrAction, std::string>>>> ok = {
      {kSimple,
       {{press_, "/user/hand/left/input/select/click"},
        {press_, "/user/hand/right/input/menu/click"},
        {grip_, "/user/hand/right/input/aim/pose"},
        {buzz_, "/user/hand/left/output/haptic"}}},
      {"/interaction_profiles/google/daydream_controller",
       {{stick_, "/user/hand/left/input/trackpad"},
        {press_, "/user/hand/right/input/trackpad/touch"},
        {squeeze_, "/user/hand/left/input/trackpad/x"}}},
      {"/interaction_profiles/htc/vive_controller",
       {{squeeze_, "/user/hand/left/input/trigger/value"},
        {press_, "/user/hand/right/input/squeeze/click"},
        {buzz_, "/user/hand/right/output/haptic"}}},
      {"/interaction_profiles/htc/vive_pro",
       {{press_, "/user/head/input/volume_up/click"}, {press_, "/user/head/input/mute_mic/click"}}},
      {"/interaction_profiles/microsoft/motion_controller",
       {{stick_, "/user/hand/left/input/thumbstick"},
        {press_, "/user/hand/left/input/trackpad/click"}}},
      {"/interaction_profiles/microsoft/xbox_controller",
       {{stick_, "/user/gamepad/input/thumbstick_right"},
        {squeeze_, "/user/gamepad/input/trigger_left/value"},
        {press_, "/user/gamepad/input/dpad_up/click"},
        {buzz_, "/user/gamepad/output/haptic_left_trigger"}}},
      {"/interaction_profiles/oculus/go_controller",
       {{press_, "/user/hand/left/input/back/click"}, {grip_, "/user/hand/right/input/grip/pose"}}},
      {"/interaction_profiles/oculus/touch_controller",
       {{press_, "/user/hand/left/input/x/click"},
        {press_, "/user/hand/right/input/a/touch"},
        {squeeze_, "/user/hand/right/input/squeeze/value"},
        {press_, "/user/hand/left/input/thumbrest/touch"}}},
      {kIndex,
       {{squeeze_, "/user/hand/left/input/squeeze/force"},
        {squeeze_, "/user/hand/right/input/trackpad/force"},
        {press_, "/user/hand/right/input/system/touch"}}},
      {"/interaction_profiles/ext/eye_gaze_interaction",
       {{grip_, "/user/eyes_ext/input/gaze_ext/pose"}}},
  };
  for (const auto& [profile, list] : ok) {
    EXPECT_EQ(suggest(profile, list), XR_SUCCESS) << profile;
  }
  const std::vector<std::pair<const char*, std::string>> refused = {
      {"/interaction_profiles/acme/wand", "/user/hand/left/input/select/click"},
      {kSimple, "/user/hand/left/input/select/value"},   // no such component
      {kSimple, "/user/hand/left/input/trigger/value"},  // no such identifier
      {kSimple, "/user/head/input/select/click"},        // not on the head
      {"/interaction_profiles/oculus/touch_controller",
       "/user/hand/left/input/a/click"},  // a: right hand only
      {"/interaction_profiles/oculus/touch_controller",
       "/user/hand/left/input/trigger/click"},  // Touch triggers have no click
      {"/interaction_profiles/google/daydream_controller",
       "/user/hand/left/output/haptic"},         // Daydream has no haptics
      {kIndex, "/user/hand/left/input/haptic"},  // an output named as input
      {kIndex, "/user/hand/left/input/trigger/value/extra"}};
  for (const auto& [profile, p] : refused) {
    EXPECT_EQ(suggest(profile, {{press_, p}}), XR_ERROR_PATH_UNSUPPORTED) << profile << " " << p;
  }
  EXPECT_EQ(validation_errors(), "");
}

// The eye gaze profile is the extension's: without it, it is not one the runtime knows.
TEST_F(RuntimeInput, AnExtensionsProfileNeedsTheExtension) {
  create(/*eye_gaze=*/false);
  EXPECT_EQ(suggest("/interaction_profiles/ext/eye_gaze_interaction",
                    {{grip_, "/user/eyes_ext/input/gaze_ext/pose"}}),
            XR_ERROR_PATH_UNSUPPORTED);
}

// Bindings whose input does not fit the action's type are left unbound (and listed).
TEST_F(RuntimeInput, BindingsOfTheWrongTypeAreIgnored) {
  create();
  XR_OK(suggest(kSimple, {{grip_, "/user/hand/left/input/select/click"},
                          {press_, "/user/hand/left/input/grip/pose"},
                          {stick_, "/user/hand/left/input/menu/click"},
                          {buzz_, "/user/hand/left/input/select/click"},
                          {press_, "/user/hand/right/input/select/click"}}));
  auto ai = make<XrSessionActionSetsAttachInfo>(XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO);
  ai.countActionSets = 1;
  ai.actionSets = &set_;
  XR_OK(xrAttachSessionActionSets(session_, &ai));
  auto info =
      make<XrBoundSourcesForActionEnumerateInfo>(XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO);
  info.action = press_;
  uint32_t count = 0;
  XR_OK(xrEnumerateBoundSourcesForAction(session_, &info, 0, &count, nullptr));
  EXPECT_EQ(count, 1u);  // right select only
  destroy();
  const nlohmann::json rec = record();
  EXPECT_EQ(rec["ignored_bindings"].size(), 4u) << rec["ignored_bindings"].dump();
}

// The scripted a button, trigger and thumbstick, frame by frame, as the spec defines the states.
TEST_F(RuntimeInput, ScriptedInputsAreTheActionStates) {
  create();
  bind_and_attach();
  XrTime press_changed_at = 0;
  bool was_pressed = false;
  int focused_frames = 0;
  for (int i = 0; i < 50; ++i) {
    frame([&] {
      auto b = make<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
      auto f = make<XrActionStateFloat>(XR_TYPE_ACTION_STATE_FLOAT);
      auto v = make<XrActionStateVector2f>(XR_TYPE_ACTION_STATE_VECTOR2F);
      auto p = make<XrActionStatePose>(XR_TYPE_ACTION_STATE_POSE);
      auto left = make<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
      const auto gb = get(press_), gf = get(squeeze_, hands_[1]), gv = get(stick_, hands_[1]),
                 gp = get(grip_, hands_[0]), gl = get(press_, hands_[0]);
      ASSERT_EQ(xrGetActionStateBoolean(session_, &gb, &b), XR_SUCCESS);
      ASSERT_EQ(xrGetActionStateFloat(session_, &gf, &f), XR_SUCCESS);
      ASSERT_EQ(xrGetActionStateVector2f(session_, &gv, &v), XR_SUCCESS);
      ASSERT_EQ(xrGetActionStatePose(session_, &gp, &p), XR_SUCCESS);
      ASSERT_EQ(xrGetActionStateBoolean(session_, &gl, &left), XR_SUCCESS);
      if (sync_ == XR_SESSION_NOT_FOCUSED) {  // no input focus: nothing is active
        EXPECT_FALSE(b.isActive || f.isActive || v.isActive || p.isActive);
        return;
      }
      ASSERT_EQ(sync_, XR_SUCCESS);
      ++focused_frames;
      const double s = t();
      EXPECT_TRUE(b.isActive && f.isActive && v.isActive && p.isActive) << s;
      const bool pressed = s >= 0.1 && s < 0.4;  // the times the runtime samples, exactly
      EXPECT_EQ(b.currentState == XR_TRUE, pressed) << s;
      EXPECT_EQ(b.changedSinceLastSync == XR_TRUE, pressed != was_pressed) << s;
      if (pressed != was_pressed) {
        press_changed_at = time_;
      }
      EXPECT_EQ(b.lastChangeTime, press_changed_at) << s;
      was_pressed = pressed;
      EXPECT_FALSE(left.currentState) << "the left hand pressed nothing, t = " << s;
      EXPECT_TRUE(left.isActive);
      const double trigger = s < 0.2 ? 0.0 : s < 0.3 ? (s - 0.2) / 0.1 : 1.0;
      EXPECT_NEAR(f.currentState, trigger, 1e-4) << s;
      if (s >= 0.2 && s <= 0.3) {
        EXPECT_NEAR(v.currentState.x, 0.5f, 1e-5f) << s;
        EXPECT_NEAR(v.currentState.y, -1.0f, 1e-5f) << s;
      }
    });
  }
  EXPECT_GE(focused_frames, 45);
  EXPECT_EQ(validation_errors(), "");
}

// The headset's Index controllers are the current profile; the event comes once, at the first
// sync of the running session; bound sources and their localized names.
TEST_F(RuntimeInput, CurrentProfileEventAndBoundSources) {
  create();
  auto state = make<XrInteractionProfileState>(XR_TYPE_INTERACTION_PROFILE_STATE);
  EXPECT_EQ(xrGetCurrentInteractionProfile(session_, hands_[1], &state),
            XR_ERROR_ACTIONSET_NOT_ATTACHED);
  bind_and_attach();
  XR_OK(xrGetCurrentInteractionProfile(session_, hands_[1], &state));
  EXPECT_EQ(state.interactionProfile, path(kIndex));
  XR_OK(xrGetCurrentInteractionProfile(session_, path("/user/head"), &state));
  EXPECT_EQ(state.interactionProfile, static_cast<XrPath>(XR_NULL_PATH));  // nothing suggested
  EXPECT_EQ(xrGetCurrentInteractionProfile(session_, path("/user/hand"), &state),
            XR_ERROR_PATH_UNSUPPORTED);
  for (int i = 0; i < 5; ++i) {
    frame([] {});
  }
  poll();
  EXPECT_EQ(profile_events_, 1);

  auto info =
      make<XrBoundSourcesForActionEnumerateInfo>(XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO);
  info.action = squeeze_;
  uint32_t count = 0;
  XR_OK(xrEnumerateBoundSourcesForAction(session_, &info, 0, &count, nullptr));
  ASSERT_EQ(count, 2u);
  XrPath sources[2] = {};
  XR_OK(xrEnumerateBoundSourcesForAction(session_, &info, 2, &count, sources));
  EXPECT_EQ(sources[0], path("/user/hand/left/input/trigger/value"));
  EXPECT_EQ(sources[1], path("/user/hand/right/input/trigger/value"));

  auto ni = make<XrInputSourceLocalizedNameGetInfo>(XR_TYPE_INPUT_SOURCE_LOCALIZED_NAME_GET_INFO);
  ni.sourcePath = sources[1];
  ni.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_USER_PATH_BIT |
                       XR_INPUT_SOURCE_LOCALIZED_NAME_INTERACTION_PROFILE_BIT |
                       XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
  char text[128] = {};
  XR_OK(xrGetInputSourceLocalizedName(session_, &ni, sizeof(text), &count, text));
  EXPECT_STREQ(text, "Right Hand Index Controller Trigger Value");
  ni.whichComponents = XR_INPUT_SOURCE_LOCALIZED_NAME_COMPONENT_BIT;
  XR_OK(xrGetInputSourceLocalizedName(session_, &ni, sizeof(text), &count, text));
  EXPECT_STREQ(text, "Trigger Value");
  ni.sourcePath = path("/user/hand/right/input/select/click");  // the simple controller's
  EXPECT_EQ(xrGetInputSourceLocalizedName(session_, &ni, sizeof(text), &count, text),
            XR_ERROR_PATH_UNSUPPORTED);
  destroy();
  EXPECT_EQ(record()["profiles"]["/user/hand/left"], kIndex);
  EXPECT_EQ(validation_errors(), "");
}

// Haptics: applied and stopped while focused, recorded with the outputs they reach; checked.
TEST_F(RuntimeInput, HapticsAreRecorded) {
  create();
  bind_and_attach();
  auto hi = make<XrHapticActionInfo>(XR_TYPE_HAPTIC_ACTION_INFO);
  hi.action = buzz_;
  hi.subactionPath = hands_[1];
  auto vibration = make<XrHapticVibration>(XR_TYPE_HAPTIC_VIBRATION);
  vibration.amplitude = 0.7f;
  vibration.duration = 20'000'000;
  vibration.frequency = XR_FREQUENCY_UNSPECIFIED;
  const auto* haptic = reinterpret_cast<const XrHapticBaseHeader*>(&vibration);
  int applied = 0;
  for (int i = 0; i < 4; ++i) {
    frame([&] {
      const XrResult r = xrApplyHapticFeedback(session_, &hi, haptic);
      EXPECT_EQ(r, sync_ == XR_SUCCESS ? XR_SUCCESS : XR_SESSION_NOT_FOCUSED);
      applied += r == XR_SUCCESS ? 1 : 0;
    });
  }
  frame([&] { EXPECT_EQ(xrStopHapticFeedback(session_, &hi), XR_SUCCESS); });
  hi.action = squeeze_;
  EXPECT_EQ(xrApplyHapticFeedback(session_, &hi, haptic), XR_ERROR_ACTION_TYPE_MISMATCH);
  hi.action = buzz_;
  hi.subactionPath = path("/user/head");
  EXPECT_EQ(xrApplyHapticFeedback(session_, &hi, haptic), XR_ERROR_PATH_UNSUPPORTED);
  destroy();
  const nlohmann::json haptics = record()["haptics"];
  ASSERT_EQ(haptics.size(), static_cast<std::size_t>(applied) + 1);
  ASSERT_GE(applied, 3);
  EXPECT_FLOAT_EQ(haptics[0]["amplitude"].get<float>(), 0.7f);
  EXPECT_EQ(haptics[0]["duration"].get<std::int64_t>(), 20'000'000);
  EXPECT_EQ(haptics[0]["outputs"], nlohmann::json::array({"/user/hand/right/output/haptic"}));
  EXPECT_TRUE(haptics.back()["stop"].get<bool>());
}

// States asked wrongly: the type, a subaction path the action lacks, before attaching.
TEST_F(RuntimeInput, ActionStatesAreCheckedAsTheSpecSays) {
  create();
  auto b = make<XrActionStateBoolean>(XR_TYPE_ACTION_STATE_BOOLEAN);
  const auto gb = get(press_);
  EXPECT_EQ(xrGetActionStateBoolean(session_, &gb, &b), XR_ERROR_ACTIONSET_NOT_ATTACHED);
  bind_and_attach();
  const auto gf = get(squeeze_);
  EXPECT_EQ(xrGetActionStateBoolean(session_, &gf, &b), XR_ERROR_ACTION_TYPE_MISMATCH);
  const auto gh = get(press_, path("/user/head"));
  EXPECT_EQ(xrGetActionStateBoolean(session_, &gh, &b), XR_ERROR_PATH_UNSUPPORTED);
  auto ai = make<XrActionCreateInfo>(XR_TYPE_ACTION_CREATE_INFO);
  ai.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::strcpy(ai.actionName, "late");
  std::strcpy(ai.localizedActionName, "late");
  XrAction late = XR_NULL_HANDLE;
  EXPECT_EQ(xrCreateAction(set_, &ai, &late), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  EXPECT_EQ(validation_errors(), "");
}

// The blend modes the script's headset offers, in its order; xrEndFrame refuses another.
TEST_F(RuntimeInput, BlendModesAreTheHeadsets) {
  create();
  uint32_t count = 0;
  XR_OK(xrEnumerateEnvironmentBlendModes(
      instance_, system_, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 0, &count, nullptr));
  ASSERT_EQ(count, 2u);
  XrEnvironmentBlendMode modes[2] = {};
  XR_OK(xrEnumerateEnvironmentBlendModes(
      instance_, system_, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &count, modes));
  EXPECT_EQ(modes[0], XR_ENVIRONMENT_BLEND_MODE_ALPHA_BLEND);
  EXPECT_EQ(modes[1], XR_ENVIRONMENT_BLEND_MODE_ADDITIVE);
  bind_and_attach();
  frame([] {});  // ends in ADDITIVE
  poll();
  auto fs = make<XrFrameState>(XR_TYPE_FRAME_STATE);
  auto wi = make<XrFrameWaitInfo>(XR_TYPE_FRAME_WAIT_INFO);
  XR_OK(xrWaitFrame(session_, &wi, &fs));
  auto bi = make<XrFrameBeginInfo>(XR_TYPE_FRAME_BEGIN_INFO);
  XR_OK(xrBeginFrame(session_, &bi));
  auto ei = make<XrFrameEndInfo>(XR_TYPE_FRAME_END_INFO);
  ei.displayTime = fs.predictedDisplayTime;
  ei.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  EXPECT_EQ(xrEndFrame(session_, &ei), XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED);
  destroy();
  const nlohmann::json rec = record();
  ASSERT_EQ(rec["frames"].size(), 1u);
  EXPECT_EQ(rec["frames"][0]["blend_mode"], "ADDITIVE");
  ASSERT_EQ(rec["refusals"].size(), 1u);
  EXPECT_EQ(rec["refusals"][0]["result"], "XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED");
}

// A script's input, blend modes and profiles are checked like the rest: the message names the
// field.
TEST_F(RuntimeInput, ABadScriptInputIsRefusedNamingIt) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"keys": [{"t": 0, "input": {"right": {"trigerr": 1}}}]})",
       "keys[0].input.right.trigerr"},
      {R"({"keys": [{"t": 0, "input": {"right": {"trigger": 1.5}}}]})",
       "keys[0].input.right.trigger"},
      {R"({"keys": [{"t": 0, "input": {"tail": {"a": true}}}]})", "keys[0].input.tail"},
      {R"({"keys": [{"t": 0, "input": {"left": {"thumbstick": [0, 2]}}}]})",
       "keys[0].input.left.thumbstick[1]"},
      {R"({"blend_modes": ["SEE_THROUGH"], "keys": [{"t": 0}]})", "blend_modes[0]"},
      {R"({"blend_modes": ["OPAQUE", "OPAQUE"], "keys": [{"t": 0}]})", "blend_modes[1]"},
      {R"({"profiles": ["/interaction_profiles/acme/wand"], "keys": [{"t": 0}]})", "profiles[0]"},
      {R"({"capture_frames": [-1], "keys": [{"t": 0}]})", "capture_frames[0]"},
  };
  for (const auto& [script, field] : cases) {
    write_script(script);
    const auto [r, said] =
        with_stderr(dir_ / "stderr.txt", [this] { return create_instance(false); });
    EXPECT_EQ(r, XR_ERROR_INITIALIZATION_FAILED) << script;
    if (XR_SUCCEEDED(r)) {
      xrDestroyInstance(instance_);
    }
    instance_ = XR_NULL_HANDLE;
    EXPECT_NE(said.find(field), std::string::npos) << field << ": " << said;
  }
}

}  // namespace
}  // namespace deixis::xr
