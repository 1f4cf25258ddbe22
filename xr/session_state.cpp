#include "xr/session_state.h"

namespace deixis::xr {

const char* to_string(SessionState state) {
  switch (state) {
    case SessionState::kUnknown:
      return "UNKNOWN";
    case SessionState::kIdle:
      return "IDLE";
    case SessionState::kReady:
      return "READY";
    case SessionState::kSynchronized:
      return "SYNCHRONIZED";
    case SessionState::kVisible:
      return "VISIBLE";
    case SessionState::kFocused:
      return "FOCUSED";
    case SessionState::kStopping:
      return "STOPPING";
    case SessionState::kLossPending:
      return "LOSS_PENDING";
    case SessionState::kExiting:
      return "EXITING";
  }
  return "?";
}

SessionStep on_event(const SessionMachine& machine, const SessionEvent& event) {
  SessionStep step{machine, {}};
  SessionMachine& m = step.next;
  SessionActions& a = step.actions;
  if (m.finished) {
    return step;  // nothing more happens after the loop was left
  }
  switch (event.kind) {
    case SessionEventKind::kExitRequested:
      if (m.running) {
        // The runtime answers with STOPPING; the session ends there (spec 9.3).
        a.request_exit_session = !m.exit_requested;
        m.exit_requested = true;
      } else {
        m.finished = true;
        a.destroy = true;
      }
      return step;
    case SessionEventKind::kInstanceLossPending:
      m.finished = true;
      m.lost = true;
      a.destroy = true;
      return step;
    case SessionEventKind::kStateChanged:
      break;
  }
  m.state = event.state;
  switch (event.state) {
    case SessionState::kReady:
      if (!m.running) {
        a.begin_session = true;
        m.running = true;
      }
      break;
    case SessionState::kStopping:
      if (m.running) {
        a.end_session = true;
        m.running = false;
      }
      break;
    case SessionState::kExiting:
      m.finished = true;
      a.destroy = true;
      break;
    case SessionState::kLossPending:
      m.finished = true;
      m.lost = true;
      a.destroy = true;
      break;
    case SessionState::kUnknown:
    case SessionState::kIdle:  // after xrEndSession the runtime says EXITING or READY next
    case SessionState::kSynchronized:
    case SessionState::kVisible:
    case SessionState::kFocused:
      break;
  }
  return step;
}

}  // namespace deixis::xr
