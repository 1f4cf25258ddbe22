// The session state machine (xr/session_state.h) through the spec's lifecycle, without a runtime.

#include "xr/session_state.h"

#include <gtest/gtest.h>

namespace deixis::xr {
namespace {

SessionEvent changed(SessionState s) {
  return {SessionEventKind::kStateChanged, s};
}

TEST(SessionStateTest, FullLifecycleBeginsOnceEndsOnceAndDestroysOnExiting) {
  SessionMachine m;
  int begins = 0, ends = 0, destroys = 0;
  const SessionState order[] = {SessionState::kIdle,         SessionState::kReady,
                                SessionState::kSynchronized, SessionState::kVisible,
                                SessionState::kFocused,      SessionState::kVisible,
                                SessionState::kSynchronized, SessionState::kStopping,
                                SessionState::kIdle,         SessionState::kExiting};
  for (SessionState s : order) {
    const SessionStep step = on_event(m, changed(s));
    begins += step.actions.begin_session ? 1 : 0;
    ends += step.actions.end_session ? 1 : 0;
    destroys += step.actions.destroy ? 1 : 0;
    m = step.next;
    EXPECT_EQ(m.state, s);
    const bool between = s == SessionState::kReady || s == SessionState::kSynchronized ||
                         s == SessionState::kVisible || s == SessionState::kFocused;
    EXPECT_EQ(runs_frame_loop(m), between) << to_string(s);
    EXPECT_EQ(syncs_actions(m), s == SessionState::kFocused) << to_string(s);
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(ends, 1);
  EXPECT_EQ(destroys, 1);
  EXPECT_TRUE(m.finished);
  EXPECT_FALSE(m.lost);
}

TEST(SessionStateTest, IdleAloneDoesNothing) {
  const SessionStep step = on_event({}, changed(SessionState::kIdle));
  EXPECT_FALSE(step.actions.begin_session || step.actions.end_session || step.actions.destroy);
  EXPECT_FALSE(runs_frame_loop(step.next));
}

TEST(SessionStateTest, ReadyAgainAfterStoppingBeginsAgain) {
  SessionMachine m;
  for (SessionState s :
       {SessionState::kIdle, SessionState::kReady, SessionState::kStopping, SessionState::kIdle}) {
    m = on_event(m, changed(s)).next;
  }
  const SessionStep again = on_event(m, changed(SessionState::kReady));
  EXPECT_TRUE(again.actions.begin_session);
  EXPECT_TRUE(runs_frame_loop(again.next));
}

TEST(SessionStateTest, ExitRequestWhileRunningAsksTheRuntimeOnceThenEndsOnStopping) {
  SessionMachine m = on_event({}, changed(SessionState::kReady)).next;
  m = on_event(m, changed(SessionState::kFocused)).next;
  SessionStep step = on_event(m, {SessionEventKind::kExitRequested, {}});
  EXPECT_TRUE(step.actions.request_exit_session);
  EXPECT_FALSE(step.actions.destroy);
  EXPECT_TRUE(runs_frame_loop(step.next));  // frames go on until STOPPING
  step = on_event(step.next, {SessionEventKind::kExitRequested, {}});
  EXPECT_FALSE(step.actions.request_exit_session);
  step = on_event(step.next, changed(SessionState::kStopping));
  EXPECT_TRUE(step.actions.end_session);
  step = on_event(step.next, changed(SessionState::kIdle));
  EXPECT_FALSE(step.actions.destroy);
  step = on_event(step.next, changed(SessionState::kExiting));
  EXPECT_TRUE(step.actions.destroy);
}

TEST(SessionStateTest, ExitRequestBeforeTheSessionRunsDestroysAtOnce) {
  const SessionStep step = on_event(on_event({}, changed(SessionState::kIdle)).next,
                                    {SessionEventKind::kExitRequested, {}});
  EXPECT_FALSE(step.actions.request_exit_session);
  EXPECT_TRUE(step.actions.destroy);
  EXPECT_TRUE(step.next.finished);
}

TEST(SessionStateTest, LossPendingLeavesTheLoopWithoutEndingTheSession) {
  SessionMachine m = on_event({}, changed(SessionState::kReady)).next;
  const SessionStep step = on_event(m, changed(SessionState::kLossPending));
  EXPECT_TRUE(step.actions.destroy);
  EXPECT_FALSE(step.actions.end_session);
  EXPECT_TRUE(step.next.lost);
  EXPECT_FALSE(runs_frame_loop(step.next));
}

TEST(SessionStateTest, InstanceLossPendingDestroys) {
  SessionMachine m = on_event({}, changed(SessionState::kReady)).next;
  const SessionStep step = on_event(m, {SessionEventKind::kInstanceLossPending, {}});
  EXPECT_TRUE(step.actions.destroy);
  EXPECT_TRUE(step.next.lost);
}

TEST(SessionStateTest, NothingHappensAfterFinishing) {
  SessionMachine m = on_event({}, changed(SessionState::kExiting)).next;
  ASSERT_TRUE(m.finished);
  const SessionStep step = on_event(m, changed(SessionState::kReady));
  EXPECT_FALSE(step.actions.begin_session || step.actions.destroy);
  EXPECT_FALSE(runs_frame_loop(step.next));
}

TEST(SessionStateTest, StoppingWithoutRunningDoesNotEnd) {
  const SessionStep step = on_event({}, changed(SessionState::kStopping));
  EXPECT_FALSE(step.actions.end_session);
}

}  // namespace
}  // namespace deixis::xr
