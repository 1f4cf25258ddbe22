// The panel's network form without a window: what it shows first (the flags' session, else a
// join of 127.0.0.1 at the default port), the session options it starts — the same as the flags
// give — and what it refuses, saying why; and the simulator's clock, which a session started
// from the panel turns from fixed steps to the wall clock without a jump back.

#include <gtest/gtest.h>

#include <cstdio>
#include <thread>

#include "sim/sim_network_form.h"
#include "sim/sim_time.h"
#include "site/endpoint.h"

namespace deixis::sim {
namespace {

template <std::size_t N>
void set(std::array<char, N>& field, const char* text) {
  std::snprintf(field.data(), field.size(), "%s", text);
}

TEST(SimNetworkFormTest, WithoutFlagsItJoinsTheLoopbackAtTheDefaultPort) {
  const NetworkForm form = initial_network_form(sim::SimOptions{});
  EXPECT_FALSE(form.host);
  EXPECT_STREQ(form.endpoint.data(), "127.0.0.1:7350");
  EXPECT_STREQ(form.port.data(), "7350");
  EXPECT_STREQ(form.passphrase.data(), "");
  const FormSession s = form_session(form);
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->role, net::Role::kJoiner);
  EXPECT_EQ(s.options->address, "127.0.0.1");
  EXPECT_EQ(s.options->port, 7350);
  EXPECT_EQ(s.options->wait, 30.0);
}

TEST(SimNetworkFormTest, TheFlagsFillItAndItStartsWhatTheyWould) {
  sim::SimOptions join;
  join.network = true;
  join.host = false;
  join.address = "10.0.0.2";
  join.port = 7400;
  join.passphrase = "blue whale";
  join.wait = 5.0;
  NetworkForm form = initial_network_form(join);
  EXPECT_FALSE(form.host);
  EXPECT_STREQ(form.endpoint.data(), "10.0.0.2:7400");
  EXPECT_STREQ(form.port.data(), "7350");  // hosting instead listens on the default port
  FormSession s = form_session(form);
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->role, net::Role::kJoiner);
  EXPECT_EQ(s.options->address, "10.0.0.2");
  EXPECT_EQ(s.options->port, 7400);
  EXPECT_EQ(s.options->passphrase, "blue whale");
  EXPECT_EQ(s.options->wait, 5.0);

  sim::SimOptions host;
  host.network = true;
  host.host = true;
  host.address = "127.0.0.1";  // --bind
  host.port = 0;
  form = initial_network_form(host);
  EXPECT_TRUE(form.host);
  EXPECT_STREQ(form.port.data(), "0");
  s = form_session(form);
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->role, net::Role::kHost);
  EXPECT_EQ(s.options->address, "127.0.0.1");
  EXPECT_EQ(s.options->port, 0);
  EXPECT_EQ(s.options->passphrase, "");

  // Without --host, a host started from the panel listens where --bind's default does.
  form = initial_network_form(join);
  form.host = true;
  s = form_session(form);
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->address, sim::SimOptions{}.address);
  EXPECT_EQ(s.options->port, 7350);
}

// The problem the form's Start finds with `text` in the join field (empty: none).
std::string join_problem(const char* text) {
  NetworkForm form = initial_network_form(sim::SimOptions{});
  set(form.endpoint, text);
  return form_session(form).problem;
}

std::string host_problem(const char* port) {
  NetworkForm form = initial_network_form(sim::SimOptions{});
  form.host = true;
  set(form.port, port);
  return form_session(form).problem;
}

TEST(SimNetworkFormTest, ARoomsNameMakesItARoomOnTheRelay) {
  // The flags' room fills the form; Start enters that room on the relay, as --connect --room.
  sim::SimOptions flags;
  flags.network = true;
  flags.host = false;
  flags.address = "127.0.0.1";
  flags.port = 7351;
  flags.room = "meeting";
  flags.passphrase = "blue whale";
  flags.wait = 8.0;
  NetworkForm form = initial_network_form(flags);
  EXPECT_STREQ(form.room.data(), "meeting");
  FormSession s = form_session(form);
  EXPECT_FALSE(s.options.has_value());
  ASSERT_TRUE(s.room.has_value()) << s.problem;
  EXPECT_EQ(s.room->relay_host, "127.0.0.1");
  EXPECT_EQ(s.room->relay_port, 7351);
  EXPECT_EQ(s.room->room, "meeting");
  EXPECT_EQ(s.room->passphrase, "blue whale");
  EXPECT_EQ(s.room->wait, 8.0);

  // Without a name it is a direct join of the same address; hosting ignores the name.
  set(form.room, "");
  s = form_session(form);
  EXPECT_FALSE(s.room.has_value());
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->port, 7351);
  set(form.room, "meeting");
  form.host = true;
  EXPECT_FALSE(form_session(form).room.has_value());
  form.host = false;

  // A name with a control character, a bad relay address, and an open room through a relay
  // beyond this machine (without --open) are refused, saying why.
  set(form.room, "a\tb");
  s = form_session(form);
  EXPECT_FALSE(s.room.has_value() || s.options.has_value());
  EXPECT_NE(s.problem.find("room name"), std::string::npos) << s.problem;
  set(form.room, "meeting");
  set(form.endpoint, "127.0.0.1");
  s = form_session(form);
  EXPECT_FALSE(s.room.has_value() || s.options.has_value());
  EXPECT_EQ(s.problem.rfind("Room: ", 0), 0u) << s.problem;
  set(form.endpoint, "192.0.2.1:7351");
  set(form.passphrase, "");
  site::allow_open_sessions(false);
  s = form_session(form);
  EXPECT_FALSE(s.room.has_value() || s.options.has_value());
  EXPECT_NE(s.problem.find("--open"), std::string::npos) << s.problem;
  set(form.passphrase, "blue whale");
  EXPECT_TRUE(form_session(form).room.has_value());
}

TEST(SimNetworkFormTest, WhatCannotStartSaysWhy) {
  EXPECT_EQ(join_problem("192.168.1.20:7350"), "");
  EXPECT_NE(join_problem("127.0.0.1").find("expected HOST:PORT"), std::string::npos);
  EXPECT_NE(join_problem("127.0.0.1:99999").find("the port must be 1 to 65535"), std::string::npos);
  EXPECT_NE(join_problem("127.0.0.1:x").find("the port must be a number"), std::string::npos);
  // A name would be looked up inside the frame loop: the panel refuses it, naming the flag.
  EXPECT_NE(join_problem("localhost:7350").find("numeric address"), std::string::npos);
  EXPECT_NE(join_problem("localhost:7350").find("--join"), std::string::npos);
  EXPECT_EQ(host_problem("0"), "");
  EXPECT_EQ(host_problem("65535"), "");
  EXPECT_NE(host_problem("65536").find("expected 0 to 65535"), std::string::npos);
  EXPECT_NE(host_problem("").find("Host: port ''"), std::string::npos);
  EXPECT_NE(host_problem("12x").find("expected 0 to 65535"), std::string::npos);
}

TEST(SimNetworkFormTest, AHostBeyondLoopbackNeedsAPassphraseOrOpen) {
  // The panel hosts where --bind said (127.0.0.1 by default); beyond loopback without a
  // passphrase it refuses, saying what to do, unless the command line allowed open sessions.
  sim::SimOptions flags;
  flags.network = true;
  flags.host = true;
  flags.address = "0.0.0.0";
  flags.port = 0;
  NetworkForm form = initial_network_form(flags);
  EXPECT_EQ(form.bind, "0.0.0.0");
  FormSession s = form_session(form);
  EXPECT_FALSE(s.options.has_value());
  EXPECT_NE(s.problem.find("reaches beyond this machine"), std::string::npos) << s.problem;
  EXPECT_NE(s.problem.find("--open"), std::string::npos) << s.problem;
  set(form.passphrase, "blue whale");
  s = form_session(form);
  ASSERT_TRUE(s.options.has_value()) << s.problem;
  EXPECT_EQ(s.options->address, "0.0.0.0");
  set(form.passphrase, "");
  site::allow_open_sessions(true);
  s = form_session(form);
  site::allow_open_sessions(false);
  ASSERT_TRUE(s.options.has_value()) << s.problem;

  // Loopback in any spelling that resolves into 127.0.0.0/8 is fine without.
  for (const char* bind : {"127.0.0.1", "127.1.2.3", "localhost"}) {
    form.bind = bind;
    EXPECT_TRUE(form_session(form).options.has_value()) << bind;
  }
  EXPECT_EQ(initial_network_form(sim::SimOptions{}).bind, "127.0.0.1");
  EXPECT_TRUE(site::binds_loopback_only("127.0.0.1"));
  EXPECT_FALSE(site::binds_loopback_only("0.0.0.0"));
  EXPECT_FALSE(site::binds_loopback_only("10.0.0.2"));
  EXPECT_FALSE(site::binds_loopback_only(""));
}

TEST(SimTimeTest, FixedStepsThenTheWallClockFromWhereTheyStopped) {
  SimTime time(true);
  EXPECT_EQ(time.next_frame(), 0.0);
  EXPECT_DOUBLE_EQ(time.next_frame(), SimTime::kTick);
  EXPECT_DOUBLE_EQ(time.next_frame(), 2 * SimTime::kTick);  // steps, however long frames take
  time.follow_wall_clock();
  EXPECT_FALSE(time.fixed());
  const double first = time.next_frame();
  EXPECT_GE(first, 2 * SimTime::kTick);  // no jump back
  EXPECT_LT(first, 2 * SimTime::kTick + 0.5);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const double later = time.next_frame();
  EXPECT_GE(later - first, 0.045);  // the wall clock, not a tick a frame
  time.follow_wall_clock();         // already on it: nothing changes
  EXPECT_GE(time.next_frame(), later);

  SimTime wall(false);
  EXPECT_LT(wall.next_frame(), 0.5);
  EXPECT_FALSE(wall.fixed());
}

}  // namespace
}  // namespace deixis::sim
