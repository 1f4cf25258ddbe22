// Rooms of several people with real processes (docs/relay.md, docs/rooms-protocol.md): a
// `deixis relay` and three `deixis join --room` sites on 127.0.0.1, each in its own room (sites
// a, b and c), each showing the other two people as avatars that follow them. Every wait is
// bounded (room_children.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include "app/room_children.h"

namespace deixis::app {
namespace {

// Three rooms meet; site c's link loses a fifth of its tracking on purpose. Everyone sees the two
// others, frames flow from each, and only c's avatar misses frames.
TEST(Rooms, ThreeSitesSeeEachOtherAndOnePersonsLossStaysTheirs) {
  testing::ScratchDir dir;
  set_passphrase("three rooms, one meeting");
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  Deixis a(join_args(port, "meeting", "a.json", dir.path() / "a", 12.0));
  Deixis b(join_args(port, "meeting", "b.json", dir.path() / "b", 12.0));
  Deixis c(join_args(port, "meeting", "c.json", dir.path() / "c", 12.0) +
           std::vector<std::string>{"--drop-tracking", "0.2"});
  finish(relay, {&a, &b, &c});

  const std::map<std::string, std::vector<std::string>> others = {
      {"a", {"B", "C"}}, {"b", {"A", "C"}}, {"c", {"A", "B"}}};
  for (const auto& [name, expected] : others) {
    SCOPED_TRACE("site " + name);
    const json session = session_of(dir.path() / name);
    const std::map<std::string, json> people = people_of(session);
    ASSERT_EQ(people.size(), 2u) << session.dump(2);
    for (const std::string& other : expected) {
      ASSERT_TRUE(people.count(other)) << other << " missing: " << session.dump(2);
      const json& p = people.at(other);
      // Sites start up to a few seconds apart (more in a sanitizer build) and run 12 s each:
      // at least 3.3 s of frames overlap.
      EXPECT_GT(p["frames_played"].get<long>(), 100) << p.dump();
      EXPECT_GT(p["visible_ticks"].get<long>(), 100) << p.dump();
    }
  }
  // c drops a fifth of its frames before they leave: a and b miss c's, not each other's.
  for (const auto& [name, other] : {std::pair{"a", "B"}, std::pair{"b", "A"}}) {
    const std::map<std::string, json> people = people_of(session_of(dir.path() / name));
    const auto missed_share = [&](const std::string& who) {
      const json& p = people.at(who);
      const double played = p["frames_played"].get<double>();
      const double missed = p["frames_missed"].get<double>();
      return missed / std::max(1.0, played + missed);
    };
    // A loaded machine may make anyone's frames late now and then; C's loss comes on top.
    EXPECT_GT(missed_share("C"), 0.10) << name;
    EXPECT_GT(missed_share("C"), missed_share(other) + 0.08) << name;
  }
}

// A sealed room: a member with another passphrase sees no one and is seen by no one; a fourth
// member finds the room full (--max-people 3) and is told so.
TEST(Rooms, AWrongPassphraseSeesNoOneAndAFullRoomIsRefused) {
  testing::ScratchDir dir;
  Deixis relay({"relay", "--port", "0", "--max-people", "3"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  set_passphrase("the right one");
  Deixis a(join_args(port, "sealed", "a.json", dir.path() / "a", 8.0));
  Deixis b(join_args(port, "sealed", "b.json", dir.path() / "b", 8.0));
  set_passphrase("a wrong one");
  Deixis c(join_args(port, "sealed", "c.json", dir.path() / "c", 8.0));
  // Once three are in (the relay logs "(3 now"), a fourth is refused.
  ASSERT_TRUE(relay.wait_for_text("(3 now", 60.0)) << relay.out() << relay.err();
  set_passphrase("the right one");
  Deixis d(join_args(port, "sealed", "a.json", dir.path() / "d", 5.0));
  EXPECT_EQ(d.wait(), 1) << d.err();
  EXPECT_NE(d.err().find("room is full"), std::string::npos) << d.err();
  finish(relay, {&a, &b, &c});

  const auto a_people = people_of(session_of(dir.path() / "a"));
  const auto b_people = people_of(session_of(dir.path() / "b"));
  const auto c_people = people_of(session_of(dir.path() / "c"));
  EXPECT_EQ(a_people.size(), 1u);
  EXPECT_TRUE(a_people.count("B"));
  EXPECT_EQ(b_people.size(), 1u);
  EXPECT_TRUE(b_people.count("A"));
  EXPECT_TRUE(c_people.empty()) << "the wrong passphrase saw someone";
}

// An open room through a relay beyond this machine: refused (exit 2) unless --open says so; a
// room name the wire cannot carry, or --room flags without a room, are bad flags too.
TEST(Rooms, AnOpenRoomBeyondLoopbackNeedsOpenAndBadRoomFlagsExit2) {
  set_passphrase(nullptr);
  const std::string a = site("a.json").string();
  expect_refused({
      {{"join", "--connect", "192.0.2.1:7351", "--room", "R", "--site", a}, "--open"},
      {{"join", "--connect", "127.0.0.1:7351", "--room", "", "--site", a}, "--room"},
      {{"join", "--connect", "127.0.0.1:7351", "--drop-tracking", "0.2", "--site", a}, "--room"},
      {{"join", "--connect", "127.0.0.1:7351", "--room", "R", "--drop-tracking", "2", "--site", a},
       "--drop-tracking"},
  });
}

}  // namespace
}  // namespace deixis::app
