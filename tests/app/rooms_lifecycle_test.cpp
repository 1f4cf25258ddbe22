// Rooms of several people under real-life events, with real processes on 127.0.0.1
// (docs/relay.md, "What the process tests prove"): a person who drops out (Ctrl-C) and joins again,
// the relay killed and restarted on its port, two rooms on one relay, and one person's gaze at
// another landing on that person's avatar in a third room. Every wait is bounded
// (room_children.h); each test takes 10–25 s.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <string>
#include <thread>
#include <tuple>

#include "app/room_children.h"
#include "core/target_map.h"

namespace deixis::app {
namespace {

constexpr double kTickHz = 30.0;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A test-only site file: the demo's `base` (assets/sites) renamed `name`, its files found from
// anywhere, and, if given, another script and capture subject for its virtual user.
std::filesystem::path site_variant(const std::filesystem::path& dir, const char* base,
                                   const std::string& name, const json& script = json(),
                                   const char* subject = nullptr) {
  json config;
  {
    std::ifstream in(site(base));
    config = json::parse(in);
  }
  const std::filesystem::path from = site(base).parent_path();
  config["site"] = name;
  config["target_map"] = (from / config["target_map"].get<std::string>()).string();
  json& avatar = config["remote_avatar"]["avatar"];
  avatar = (from / avatar.get<std::string>()).string();
  if (!script.is_null()) {
    config["virtual_user"]["script"] = script;
  }
  if (subject != nullptr) {
    config["virtual_user"]["subject"] = subject;
  }
  const std::filesystem::path path = dir / (name + ".json");
  std::ofstream(path) << config.dump(2);
  return path;
}

long frames_played(const json& person) {
  return person["frames_played"].get<long>();
}

// C drops out mid-session (Ctrl-C: no goodbye, the relay notices the silence) and a new C
// process joins the same room a little later. A and B see C's avatar go (hidden, spot freed: the
// new C gets a spot among two) and come back, playing C's frames again; B, there all along, is
// untouched.
TEST(RoomsLifecycle, APersonWhoDropsOutAndJoinsAgainIsSeenToGoAndComeBack) {
  testing::ScratchDir dir;
  set_passphrase("leave and come back");
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  Deixis a(join_args(port, "meeting", "a.json", dir.path() / "a", 18.0));
  Deixis b(join_args(port, "meeting", "b.json", dir.path() / "b", 18.0));
  const auto c1_started = Clock::now();
  std::optional<Deixis> c1(std::in_place,
                           join_args(port, "meeting", "c.json", dir.path() / "c1", 60.0));
  ASSERT_TRUE(wait_for_count(a, "C is here", 1, 30.0)) << a.out() << a.err();
  ASSERT_TRUE(wait_for_count(b, "C is here", 1, 30.0)) << b.out() << b.err();
  std::this_thread::sleep_for(std::chrono::seconds(2));  // C's avatar plays at A and B
  c1->send_signal(SIGINT);
  // C1 sent at most this many frames (30 Hz since it started, and one to spare).
  const double c1_frames_at_most = seconds_since(c1_started) * kTickHz + 1.0;
  EXPECT_EQ(c1->wait(), 128 + SIGINT) << c1->err();
  c1.reset();
  // No goodbye: the relay lets C go after its silence time-out (3 s) and tells A and B.
  const auto stopped = Clock::now();
  EXPECT_TRUE(wait_for_count(a, "C left", 1, 6.0)) << a.out() << a.err();
  EXPECT_TRUE(wait_for_count(b, "C left", 1, 6.0)) << b.out() << b.err();
  const double noticed_s = seconds_since(stopped);
  std::this_thread::sleep_for(std::chrono::seconds(1));  // C's spot stays empty a while
  Deixis c2(join_args(port, "meeting", "c.json", dir.path() / "c2", 14.0));
  EXPECT_TRUE(wait_for_count(a, "C is here", 2, 30.0)) << a.out() << a.err();
  EXPECT_TRUE(wait_for_count(b, "C is here", 2, 30.0)) << b.out() << b.err();
  finish(relay, {&a, &b, &c2});
  std::printf("C's departure noticed by A and B after %.1f s\n", noticed_s);

  for (const char* name : {"a", "b"}) {
    SCOPED_TRACE(std::string("site ") + name);
    const json session = session_of(dir.path() / name);
    const std::map<std::string, json> people = people_of(session);
    ASSERT_EQ(people.size(), 2u) << session.dump(2);
    ASSERT_TRUE(people.count("C") && people.count(name == std::string("a") ? "B" : "A"));
    const json& c = people.at("C");
    const json& other = people.at(name == std::string("a") ? "B" : "A");
    EXPECT_EQ(c["stays"].get<int>(), 2) << c.dump();
    EXPECT_EQ(other["stays"].get<int>(), 1) << other.dump();
    // Frames of C played after the rejoin: more than the first C could ever have sent.
    EXPECT_GT(frames_played(c), c1_frames_at_most + 90)
        << c.dump() << " C1 at most " << c1_frames_at_most;
    // Hidden while away (at least the 3 s before the relay noticed and the second's start-up),
    // while the other person was shown throughout.
    EXPECT_LT(c["visible_ticks"].get<long>() + 90, other["visible_ticks"].get<long>())
        << c.dump() << other.dump();
    EXPECT_GT(frames_played(other), 400) << other.dump();
  }
  // The second C sees A and B.
  const std::map<std::string, json> seen = people_of(session_of(dir.path() / "c2"));
  ASSERT_EQ(seen.size(), 2u);
  for (const char* who : {"A", "B"}) {
    ASSERT_TRUE(seen.count(who)) << who;
    EXPECT_EQ(seen.at(who)["stays"].get<int>(), 1);
    EXPECT_GT(frames_played(seen.at(who)), 90) << seen.at(who).dump();
  }
}

// The relay is killed (SIGKILL: no goodbye to anyone) and a new one starts on the same port 2 s
// later. Every site notices, reconnects by itself and is back in the room seeing both others
// within 5 s of the new relay listening, then plays their frames again.
TEST(RoomsLifecycle, EverySiteIsBackWithin5sOfARestartedRelay) {
  testing::ScratchDir dir;
  set_passphrase("the relay comes back");
  std::optional<Deixis> relay(std::in_place, std::vector<std::string>{"relay", "--port", "0"});
  const int port = relay->port();
  ASSERT_GT(port, 0) << relay->err();
  const auto sites_started = Clock::now();
  Deixis a(join_args(port, "meeting", "a.json", dir.path() / "a", 16.0));
  Deixis b(join_args(port, "meeting", "b.json", dir.path() / "b", 16.0));
  Deixis c(join_args(port, "meeting", "c.json", dir.path() / "c", 16.0));
  Deixis* sites[] = {&a, &b, &c};
  for (Deixis* s : sites) {  // each sees both others
    ASSERT_TRUE(wait_for_count(*s, " is here", 2, 30.0)) << s->out() << s->err();
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));
  relay->send_signal(SIGKILL);
  // Each site played at most this many frames of each other before the relay went.
  const double before_frames_at_most = seconds_since(sites_started) * kTickHz + 1.0;
  EXPECT_EQ(relay->wait(), 128 + SIGKILL);
  relay.reset();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  Deixis again({"relay", "--port", std::to_string(port)});
  ASSERT_EQ(again.port(), port) << again.err();
  const auto restarted = Clock::now();
  double back_s = 0.0;
  for (Deixis* s : sites) {
    // Everyone was lost with the relay, then both others are here again.
    EXPECT_TRUE(wait_for_count(*s, " is here", 4, 5.0 - seconds_since(restarted)))
        << s->out() << s->err();
    back_s = seconds_since(restarted);
    EXPECT_EQ(count_of(*s, "(relay lost)"), 2) << s->out();
    EXPECT_EQ(count_of(*s, "lost: the relay"), 1) << s->out();
  }
  EXPECT_LE(back_s, 5.0);
  std::printf("every site back in the room %.2f s after the relay listened again\n", back_s);
  finish(again, {&a, &b, &c});

  for (const char* name : {"a", "b", "c"}) {
    SCOPED_TRACE(std::string("site ") + name);
    const std::map<std::string, json> people = people_of(session_of(dir.path() / name));
    ASSERT_EQ(people.size(), 2u);
    for (const auto& [who, p] : people) {
      EXPECT_EQ(p["stays"].get<int>(), 2) << who << p.dump();
      // Frames played after the restart: more than could have come before it.
      EXPECT_GT(frames_played(p), before_frames_at_most + 90)
          << who << p.dump() << " before at most " << before_frames_at_most;
    }
  }
}

// Rooms R1 (A, B) and R2 (C, D) on one relay at once: each person sees the other of their room,
// nobody sees anyone of the other room.
TEST(RoomsLifecycle, TwoRoomsOnOneRelayNeverSeeEachOther) {
  testing::ScratchDir dir;
  set_passphrase(nullptr);  // open rooms: the relay's room tokens alone keep them apart
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  ASSERT_GT(port, 0) << relay.err();
  const std::filesystem::path d_site = site_variant(dir.path(), "b.json", "D");
  Deixis a(join_args(port, "R1", "a.json", dir.path() / "a", 8.0));
  Deixis b(join_args(port, "R1", "b.json", dir.path() / "b", 8.0));
  Deixis c(join_args(port, "R2", "c.json", dir.path() / "c", 8.0));
  Deixis d(join_args(port, "R2", d_site, dir.path() / "d", 8.0));
  finish(relay, {&a, &b, &c, &d});

  const std::map<std::string, std::string> partner = {
      {"a", "B"}, {"b", "A"}, {"c", "D"}, {"d", "C"}};
  for (const auto& [name, other] : partner) {
    SCOPED_TRACE("site " + name);
    const json session = session_of(dir.path() / name);
    const std::map<std::string, json> people = people_of(session);
    ASSERT_EQ(people.size(), 1u) << session.dump(2);
    ASSERT_TRUE(people.count(other)) << session.dump(2);
    EXPECT_GT(frames_played(people.at(other)), 100) << people.at(other).dump();
  }
  // Two rooms of two on the relay at once.
  EXPECT_EQ(count_of(relay, "(2 now"), 2) << relay.out() << relay.err();
}

// What room Z saw of X looking at Y: X's avatar's gaze error at each hold of X's eyes on Y.
struct GazesAtY {
  std::vector<double> error_deg;          // the avatar's eyes (settled, presence/gaze_settle.h)
  std::vector<double> network_error_deg;  // the networks' own gaze
  json record;                            // Z's record of X
};

// Three sites `z`, `x`, `y` (site files of assets/sites, sites named as upper-case letters) enter
// one after the other, each once the earlier ones met, so that every room places people on its
// spots in a known order (the order it met them): at Z, X on the first spot and Y on the second;
// at X, Z then Y, as X's script names them (the k-th person a script names is expected on spot
// k). X's user looks at Z (long enough for Y to arrive), at Y, then at an object, over and over; Y
// rests (its head keeps still). `x_subject`: another capture subject for X's user.
GazesAtY x_looks_at_y_seen_from_z(const char* z, const char* x, const char* y,
                                  const char* x_subject = nullptr) {
  const auto name = [](const char* file) {
    return std::string(1, static_cast<char>(file[0] - 32));
  };
  const std::string Z = name(z), X = name(x), Y = name(y);
  testing::ScratchDir dir;
  set_passphrase("where X looks");
  Deixis relay({"relay", "--port", "0"});
  const int port = relay.port();
  EXPECT_GT(port, 0) << relay.err();
  const json x_script = json::parse(R"([
      { "action": "look_at", "person": ")" +
                                    Z + R"(", "seconds": 2.5 },
      { "action": "look_at", "person": ")" +
                                    Y + R"(", "seconds": 1.5 },
      { "action": "look_at", "target": 1, "seconds": 0.5 }
    ])");
  const json y_script = json::parse(R"([{ "action": "rest", "seconds": 30 }])");
  GazesAtY seen;
  Deixis z_site(join_args(port, "meeting", z, dir.path() / Z, 16.0));
  if (!relay.wait_for_text("(1 now", 30.0)) {
    ADD_FAILURE() << relay.out() << relay.err();
    return seen;
  }
  Deixis x_site(join_args(port, "meeting", site_variant(dir.path(), x, X, x_script, x_subject),
                          dir.path() / X, 16.0));
  EXPECT_TRUE(wait_for_count(z_site, X + " is here", 1, 30.0)) << z_site.out() << z_site.err();
  EXPECT_TRUE(wait_for_count(x_site, Z + " is here", 1, 30.0)) << x_site.out() << x_site.err();
  Deixis y_site(
      join_args(port, "meeting", site_variant(dir.path(), y, Y, y_script), dir.path() / Y, 14.0));
  finish(relay, {&z_site, &x_site, &y_site});

  // Y's person target: Y's member id, as Z logged it ("member N is Y").
  std::smatch m;
  const std::string z_log = z_site.out() + z_site.err();
  if (!std::regex_search(z_log, m, std::regex("member ([0-9]+) is " + Y))) {
    ADD_FAILURE() << z_log;
    return seen;
  }
  const TargetId y_target = person_target(static_cast<PersonId>(std::stoi(m[1])));
  const std::map<std::string, json> people = people_of(session_of(dir.path() / Z));
  if (!people.count(X)) {
    ADD_FAILURE() << "room " << Z << " did not see " << X;
    return seen;
  }
  seen.record = people.at(X);
  for (const json& g : seen.record["gazes"]) {
    if (g["target"].get<TargetId>() == y_target) {
      seen.error_deg.push_back(g["error_deg"].get<double>());
      seen.network_error_deg.push_back(g["network_error_deg"].get<double>());
    }
  }
  std::printf("in room %s, %s's (subject %s) avatar's gaze at %s's avatar off by", Z.c_str(),
              X.c_str(), x_subject != nullptr ? x_subject : "of the site file", Y.c_str());
  for (std::size_t i = 0; i < seen.error_deg.size(); ++i) {
    std::printf(" %.1f° (networks %.1f°)", seen.error_deg[i], seen.network_error_deg[i]);
  }
  std::printf("\n");
  return seen;
}

// A looks at C; in room B, A's avatar (on B's first spot) turns to C's avatar (on the second)
// and its gaze lands within 5° of C's avatar's eyes at every hold. Rooms A and B have their
// spots in the same places, so A's avatar turns as far and to the same side as A's user did.
TEST(RoomsLifecycle, GazeOfXAtYLandsOnYsAvatarInTheThirdRoom) {
  const GazesAtY seen = x_looks_at_y_seen_from_z("b.json", "a.json", "c.json");
  // About 14 s of A with C there: two or three looks at C held long enough.
  EXPECT_GE(seen.error_deg.size(), 2u) << seen.record.dump();
  for (double e : seen.error_deg) {
    EXPECT_LE(e, 5.0) << seen.record.dump();
  }
}

// A left-handed person's gaze at another person lands too (capture subjects 173 and 174: A's
// user made left-handed, and site C's own). The networks' gaze misses by 6–11° here (through the
// right-hand weights on the person's mirror image, decision 68; 22–39° with the left-hand
// weights), and gaze settling (presence/gaze_settle.h, decision 70) brings the avatar's eyes the
// rest of the way while the person's own eyes are on their target; its turn is bounded by 15°,
// so a networks' gaze beyond that would show here. The four pairs of decision 66, in two tests
// that ctest runs side by side.
void expect_left_handed_gazes_land(
    std::initializer_list<std::tuple<const char*, const char*, const char*, const char*>> cases) {
  for (const auto& [z, x, y, subject] : cases) {
    SCOPED_TRACE(std::string(x) + " (subject " + subject + ") looks at " + y + " seen from " + z);
    const GazesAtY seen = x_looks_at_y_seen_from_z(z, x, y, subject);
    EXPECT_GE(seen.error_deg.size(), 2u) << seen.record.dump();
    for (double e : seen.error_deg) {
      EXPECT_LE(e, 5.0) << seen.record.dump();
    }
  }
}

TEST(RoomsLifecycle, ALeftHandedPersonsGazeAtAPersonLandsToo) {
  expect_left_handed_gazes_land(
      {{"b.json", "a.json", "c.json", "173"}, {"a.json", "c.json", "b.json", "174"}});
}

TEST(RoomsLifecycle, ALeftHandedPersonsGazeAtAPersonLandsTooInTheOtherPairs) {
  expect_left_handed_gazes_land(
      {{"b.json", "c.json", "a.json", "174"}, {"a.json", "b.json", "c.json", "173"}});
}

}  // namespace
}  // namespace deixis::app
