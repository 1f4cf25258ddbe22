#pragma once
// The OpenXR session lifecycle as a pure function of events (after Khronos' hello_xr): what the
// front end must do when the runtime reports a session state, when the user asks to quit, or when
// the instance is about to be lost. No OpenXR calls here, so the rules are unit-tested without a
// runtime (tests/xr/session_state_test.cpp).
//
//   IDLE ─▶ READY ─(begin)▶ SYNCHRONIZED ─▶ VISIBLE ─▶ FOCUSED
//   FOCUSED ─▶ VISIBLE ─▶ SYNCHRONIZED ─▶ STOPPING ─(end)▶ IDLE ─▶ EXITING ─(destroy)
//   any ─▶ LOSS_PENDING ─(destroy)

#include <cstdint>

namespace deixis::xr {

// The values of XrSessionState (the front end converts; the numbers are the spec's).
enum class SessionState : std::uint8_t {
  kUnknown = 0,
  kIdle = 1,
  kReady = 2,
  kSynchronized = 3,
  kVisible = 4,
  kFocused = 5,
  kStopping = 6,
  kLossPending = 7,
  kExiting = 8,
};
const char* to_string(SessionState state);

enum class SessionEventKind : std::uint8_t {
  kStateChanged,         // XrEventDataSessionStateChanged
  kExitRequested,        // the user (or --seconds) wants to quit
  kInstanceLossPending,  // XrEventDataInstanceLossPending
};

struct SessionEvent {
  SessionEventKind kind = SessionEventKind::kStateChanged;
  SessionState state = SessionState::kUnknown;  // for kStateChanged
};

// What the front end knows about its session between events.
struct SessionMachine {
  SessionState state = SessionState::kUnknown;
  bool running = false;         // between xrBeginSession and xrEndSession
  bool exit_requested = false;  // xrRequestExitSession was asked for
  bool finished = false;        // leave the loop and destroy session and instance
  bool lost = false;            // finished because the session or instance is being lost
};

// What to call, in this order, after an event.
struct SessionActions {
  bool begin_session = false;         // xrBeginSession
  bool end_session = false;           // xrEndSession
  bool request_exit_session = false;  // xrRequestExitSession
  bool destroy = false;               // leave the loop; xrDestroySession, xrDestroyInstance
};

struct SessionStep {
  SessionMachine next;
  SessionActions actions;
};

SessionStep on_event(const SessionMachine& machine, const SessionEvent& event);

// The frame loop (xrWaitFrame, xrBeginFrame, xrEndFrame) runs while the session runs.
inline bool runs_frame_loop(const SessionMachine& m) {
  return m.running && !m.finished;
}
// Actions are synchronised (xrSyncActions) only with input focus.
inline bool syncs_actions(const SessionMachine& m) {
  return runs_frame_loop(m) && m.state == SessionState::kFocused;
}

}  // namespace deixis::xr
