#pragma once
// The test runtime's state: one instance at a time, its session, spaces, swapchains, actions and
// hand trackers, and the record of what the application submitted.
//
// Global state: the OpenXR runtime ABI hands the loader plain C function pointers with no user
// data, so the runtime's objects live in the one process-wide Runtime below (state()), guarded
// by its mutex; every entry point takes the lock. This is the only global in the project.

#include <openxr/openxr.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "xr_test_runtime/graphics_binding.h"
#include "xr_test_runtime/profiles.h"
#include "xr_test_runtime/record.h"
#include "xr_test_runtime/script.h"

namespace deixis::xrt {

enum class Source : std::uint8_t { kLeftGrip, kLeftAim, kRightGrip, kRightAim, kGaze, kHead };

struct SpaceObject {
  XrReferenceSpaceType reference = XR_REFERENCE_SPACE_TYPE_STAGE;
  bool is_action = false;
  std::uint64_t action = 0;
  XrPath subaction = XR_NULL_PATH;
  XrPosef pose_in_space{{0, 0, 0, 1}, {0, 0, 0}};
};

struct SwapchainObject {
  std::vector<std::uint32_t> textures;  // GL names, or none for a headless session
  std::int64_t format = 0;
  std::uint32_t last_released = 0;  // the image a layer shows (the last one released)
  std::uint32_t image_count = 3;
  std::uint32_t next = 0;              // the next image to acquire
  std::deque<std::uint32_t> acquired;  // in acquisition order
  bool waited = false;                 // the oldest acquired image was waited on
  std::uint32_t width = 0, height = 0;
};

// One input source an action reads after attaching: a component of an identifier of the
// interaction profile current for its top-level user path.
struct ActionBinding {
  XrPath user = XR_NULL_PATH;  // the top-level user path as the application's XrPath
  TopLevel top = TopLevel::kLeft;
  const ProfileIdentifier* identifier = nullptr;
  std::uint16_t component = 0;    // Component bits (kX | kY for a vector2)
  Source source = Source::kHead;  // for poses
  std::string path;               // the full input source path, as suggested
};

// An action's state for one subaction path (XR_NULL_PATH: all of them), as of the last
// xrSyncActions (spec §11.5: values change only when synced).
struct ActionState {
  XrPath subaction = XR_NULL_PATH;
  bool active = false;
  bool changed = false;
  XrTime last_change = 0;
  float x = 0.0f;  // boolean (0/1), float, vector2 x
  float y = 0.0f;  // vector2 y
};

struct ActionObject {
  std::uint64_t set = 0;
  XrActionType type = XR_ACTION_TYPE_POSE_INPUT;
  std::string name;
  std::string localized_name;
  std::vector<XrPath> subactions;
  std::vector<ActionBinding> bindings;  // after attach
  std::vector<ActionState> states;      // XR_NULL_PATH first, then each subaction path
};

struct ActionSetObject {
  std::string name;
  bool attached = false;
};

struct SessionObject {
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;
  bool headless = false;
  SessionGraphics graphics;  // the application's GL context (none when headless)
  bool running = false;
  bool exit_requested = false;
  bool actions_attached = false;
  bool focused_synced = false;
  // The interaction profile current for each top-level user path (nullptr: none), chosen when
  // the action sets are attached; the application hears of it at the first sync of the running
  // session (XrEventDataInteractionProfileChanged).
  std::array<const Profile*, kTopLevelCount> profiles{};
  bool profiles_announced = false;
  // Frame order: waits, begins and ends counted; a frame is begun after a wait.
  std::uint64_t waited = 0;  // frames returned by xrWaitFrame
  std::uint64_t begun = 0;   // frames begun
  std::uint64_t ended = 0;   // frames ended
  bool frame_open = false;   // between xrBeginFrame and xrEndFrame
  XrTime begun_display_time = 0;
  std::chrono::steady_clock::time_point wall_start;  // the first xrWaitFrame (realtime scripts)
};

struct Runtime {
  std::mutex mutex;
  bool instance_live = false;
  std::uint64_t next_handle = 1;
  std::vector<std::string> enabled_extensions;
  bool graphics_requirements_queried = false;
  bool system_queried = false;
  std::uint64_t instance = 0;
  std::uint64_t session = 0;  // 0: none
  SessionObject session_state;
  std::map<std::uint64_t, SpaceObject> spaces;
  std::map<std::uint64_t, SwapchainObject> swapchains;
  std::map<std::uint64_t, ActionSetObject> action_sets;
  std::map<std::uint64_t, ActionObject> actions;
  std::map<std::uint64_t, XrHandEXT> hand_trackers;
  std::vector<std::string> paths;  // XrPath n is paths[n - 1]
  // Suggested bindings by interaction profile: (action id, binding path).
  std::map<std::string, std::vector<std::pair<std::uint64_t, std::string>>> suggested;
  std::deque<XrEventDataBuffer> events;
  Script script = default_script();
  Record record;
  std::string record_path;       // DEIXIS_XR_RECORD (captured images go next to it), or empty
  XrTime epoch = 1'000'000'000;  // the first frame is predicted one period after this

  bool extension_enabled(const char* name) const;
  std::uint64_t new_handle() { return next_handle++; }
  XrTime period() const;
  // The display time input is sampled at: the last frame's predicted display time.
  XrTime input_time() const;
  XrPath find_path(std::string_view s) const;         // XR_NULL_PATH when never made
  XrPath intern(std::string_view s);                  // the path, made when new
  const std::string& path_string(XrPath path) const;  // empty for an unknown path
  // The script's sample for a display time.
  ScriptSample sample(XrTime time) const;
  // Queues a session state change (and records it).
  void change_state(XrSessionState state, XrTime time);
  // Refuses a call: records it and returns `result`.
  XrResult refuse(const char* call, XrResult result);
};

Runtime& state();

// Handles are the runtime's integer ids as the API's opaque pointer types.
template <typename H>
H to_handle(std::uint64_t id) {
  return reinterpret_cast<H>(static_cast<std::uintptr_t>(id));
}
template <typename H>
std::uint64_t from_handle(H handle) {
  return static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(handle));
}

const char* result_name(XrResult result);

// The spec's two-call idiom: the count always; the values when `capacity` holds them.
template <typename T>
XrResult two_call(uint32_t capacity, uint32_t* count, T* out, const T* values, uint32_t n) {
  if (count == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  *count = n;
  if (capacity == 0) {
    return XR_SUCCESS;
  }
  if (capacity < n || out == nullptr) {
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  for (uint32_t i = 0; i < n; ++i) {
    out[i] = values[i];
  }
  return XR_SUCCESS;
}

// Poses.
XrPosef to_xr(const ScriptPose& p);
ScriptPose from_xr(const XrPosef& p);
ScriptPose compose(const ScriptPose& a, const ScriptPose& b);  // a * b
ScriptPose inverse(const ScriptPose& p);

}  // namespace deixis::xrt
