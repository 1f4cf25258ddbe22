// The remote people a site shows (site/remote_people.h): people take the site's avatar spots in
// order of arrival, a leaving person frees theirs, one more person than spots is an error naming
// the site file; people are targets, so when X points at or looks at Y, X's avatar in room Z
// does so at Y's avatar in Z (or at Z's own user); one person's missing frames affect only their
// own avatar; a script's people by site name are resolved at run time; session.json lists one
// entry per remote person.
//
// The people's tracking is the synthetic capture's virtual user (capture/virtual_user.h)
// performing scripts in the demo rooms (assets/sites/{a,b,c}.json), translated with the authors'
// MoE weights onto the default avatar.

#include "site/remote_people.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "test_support.h"

namespace deixis::site {
namespace {

namespace fs = std::filesystem;
using Action = ScriptStep::Action;

constexpr float kDegPerRad = 57.2957795f;

float angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegPerRad;
}

SiteConfig site_config(const char* name) {
  return read_site_config(deixis::testing::source_dir() / "assets/sites" / name);
}

// Sites A and B with their spots as they are, or mirrored through the users' sagittal plane.
SiteConfig with_spots(SiteConfig site, bool mirrored) {
  if (mirrored) {
    for (Placement& p : site.spots) {
      p.floor.x() = -p.floor.x();
      p.yaw_degrees = -p.yaw_degrees;
    }
  }
  return site;
}

// What every test shares: the MoE networks by deictic hand and the default avatar's solver.
struct Shared {
  std::array<MoeNetworks, 2> networks;
  ik::AvatarSolver solver;
};

const Shared& shared() {
  static const Shared s{
      {load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
       load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)},
      ik::AvatarSolver::build(
          avatar::load_avatar(deixis::testing::source_dir() / "assets/avatars/default.glb").rig)};
  return s;
}

net::Hello hello(const std::string& site, const BodyCalibration& body = {}) {
  net::Hello h;
  h.site = site;
  h.avatar.body = body;
  return h;
}

// A person of `site` performing `script` in their own room, the people it names (by site) where
// that room's spots are, in order; their frames' scripted people replaced by `ids` (names[k] is
// person ids[k] of the room). `subject`: another capture subject than the site file's;
// `mirrored`: the room's spots mirrored (with_spots).
struct Performer {
  SiteConfig config;
  capture::ScriptPerformance performance;

  Performer(const char* site_file, const std::vector<ScriptStep>& script,
            const std::vector<std::string>& names, const std::vector<PersonId>& ids,
            double seconds = 0.0, const char* subject = nullptr, bool mirrored = false)
      : config(site_config(site_file)) {
    config = with_spots(config, mirrored);
    if (subject != nullptr) {
      config.virtual_user->subject = subject;
    }
    std::vector<capture::ScenePerson> people;
    for (std::size_t k = 0; k < names.size(); ++k) {
      people.push_back(
          {names[k], script_person_target(k), expected_person_head(config, shared().solver, k)});
    }
    const capture::VirtualUserScene scene{
        config.user.T_world_floor(), config.target_map.objects,
        presence::avatar_origin(shared().solver, config.remote_avatar.T_world_floor()).translation,
        people};
    performance = capture::perform_script(capture::find_subject(config.virtual_user->subject),
                                          script, scene, 5, seconds);
    for (TrackingFrame& f : performance.sequence.frames) {
      for (TargetId* t : {&f.head_target, &f.hand_target}) {
        if (is_script_person_target(*t)) {
          *t = person_target(ids.at(script_person_index(*t)));
        }
      }
    }
  }
  const BodyCalibration& body() const { return performance.sequence.calibration; }
  const TrackingFrame& frame(std::size_t i) const {
    const auto& frames = performance.sequence.frames;
    return frames[std::min(i, frames.size() - 1)];
  }
  std::size_t frames() const { return performance.sequence.frames.size(); }
  // The tick at which step `i` completed (the first cycle).
  std::size_t completion(std::size_t i) const {
    return static_cast<std::size_t>(std::lround(performance.steps.at(i).complete * 30.0));
  }
};

ScriptStep step(Action action, TargetId target, float seconds) {
  ScriptStep s;
  s.action = action;
  s.target = target;
  s.seconds = seconds;
  return s;
}

std::vector<ScriptStep> rest(float seconds) {
  return {step(Action::kRest, kNoTarget, seconds)};
}

TEST(RemotePeople, PeopleTakeSpotsInOrderOfArrivalAndOneTooManyNamesTheFile) {
  const SiteConfig a = site_config("a.json");
  ASSERT_EQ(a.spots.size(), 2u);
  RemotePeople people(a, shared().networks, shared().solver);
  EXPECT_EQ(people.capacity(), 2u);
  people.meet(7, hello("B"));
  people.meet(3, hello("C"));
  EXPECT_EQ(people.stats(7)->spot, 0u);
  EXPECT_EQ(people.stats(3)->spot, 1u);
  EXPECT_EQ(people.find_site("C"), 3);
  EXPECT_EQ(people.find_site("D"), kNoPerson);
  try {
    people.meet(9, hello("D"));
    ADD_FAILURE() << "a third person found a place on two spots";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("assets/sites/a.json"), std::string::npos) << message;
    EXPECT_NE(message.find("2 spot(s), all taken"), std::string::npos) << message;
  }
  EXPECT_EQ(people.size(), 2u);
  // Leaving frees the spot; the next to arrive takes it, the others stay where they are.
  people.leave(7);
  EXPECT_EQ(people.avatar(7), nullptr);
  EXPECT_EQ(people.size(), 1u);
  people.meet(9, hello("D"));
  EXPECT_EQ(people.stats(9)->spot, 0u);
  EXPECT_EQ(people.stats(3)->spot, 1u);
  // The same person met again (a new hello) keeps their spot.
  people.meet(3, hello("C"));
  EXPECT_EQ(people.stats(3)->spot, 1u);
  EXPECT_EQ(people.size(), 2u);
  people.leave(42);  // nobody: ignored
  EXPECT_EQ(people.size(), 2u);
  EXPECT_THROW(people.meet(kNoPerson, hello("E")), Error);
  EXPECT_THROW(people.meet(255, hello("E")), Error);
  // The avatars stand on their spots.
  const Pose spot1 = presence::avatar_origin(shared().solver, a.spots[1].T_world_floor());
  EXPECT_TRUE(people.avatar(3)->T_world_model().translation.isApprox(
      ik::T_world_root_from_origin(shared().solver, spot1).translation, 1e-6f));
  const Pose spot0 = presence::avatar_origin(shared().solver, a.spots[0].T_world_floor());
  EXPECT_TRUE(people.avatar(9)->T_world_model().translation.isApprox(
      ik::T_world_root_from_origin(shared().solver, spot0).translation, 1e-6f));
}

// Room A, its user person 1 at the origin; B (person 2) and C (person 3) on A's two spots.
// B, in their room, looks at A's user, then points at C; C stands at rest in theirs.
class PeopleAsTargets : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ScriptStep look_at_a = step(Action::kLookAt, script_person_target(0), 2.0f);
    look_at_a.person = "A";
    ScriptStep point_at_c = step(Action::kPoint, script_person_target(1), 2.0f);
    point_at_c.person = "C";
    b_ = new Performer("b.json", {look_at_a, point_at_c, step(Action::kRest, kNoTarget, 0.5f)},
                       {"A", "C"}, {1, 3});
    c_ = new Performer("c.json", rest(1.0f), {}, {}, static_cast<double>(b_->frames()) / 30.0);
  }
  static void TearDownTestSuite() {
    delete b_;
    delete c_;
  }

  // Plays every frame of B and C in room A; `at(i, people)` after each tick.
  template <typename At>
  std::vector<PersonRecord> run(const At& at, const RemotePeopleOptions& options = {}) {
    const SiteConfig a = site_config("a.json");
    RemotePeople people(a, shared().networks, shared().solver, options);
    people.meet(2, hello("B", b_->body()));
    people.meet(3, hello("C", c_->body()));
    const Vec3 own_head(0.0f, 1.62f, 0.0f);
    for (std::size_t i = 0; i < b_->frames(); ++i) {
      LocalTargets room{&a.target_map, own_head};
      room.people = people.people_targets(1, own_head);
      const std::array<PersonFrame, 2> frames = {PersonFrame{2, &b_->frame(i)},
                                                 PersonFrame{3, &c_->frame(i)}};
      people.tick(frames, room);
      people.end_tick();
      at(i, people, own_head);
    }
    people.finish();
    return people.records();
  }

  static Performer* b_;
  static Performer* c_;
};
Performer* PeopleAsTargets::b_ = nullptr;
Performer* PeopleAsTargets::c_ = nullptr;

// In their own room B, the scripted user turned to the spots the script's people are expected on
// (A on B's first spot, C on its second), as to objects, and their frames name those people.
TEST_F(PeopleAsTargets, TheScriptedUserTurnsToThePeoplesSpotsInTheirOwnRoom) {
  const SiteConfig& b = b_->config;
  const TrackingFrame& look = b_->frame(b_->completion(0));
  const Vec3 a_head = expected_person_head(b, shared().solver, 0);
  EXPECT_EQ(look.head_target, person_target(1));
  EXPECT_TRUE(look.head_target_position.isApprox(a_head));
  EXPECT_LT(angle_deg(look.gaze, a_head - look.T_world_head.translation), 3.0f);
  const TrackingFrame& point = b_->frame(b_->completion(1));
  const Vec3 c_head = expected_person_head(b, shared().solver, 1);
  const Vec3& tip = point.index_tip[index(b_->body().deictic_hand)];
  EXPECT_EQ(point.hand_target, person_target(3));
  EXPECT_LT(angle_deg(point.gaze, c_head - point.T_world_head.translation), 3.0f);
  EXPECT_LT(
      angle_deg(tip - point.T_world_head.translation, c_head - point.T_world_head.translation),
      6.0f);
}

TEST_F(PeopleAsTargets, BPointingAtCPointsBsAvatarAtCsAvatarInRoomA) {
  const std::size_t complete = b_->completion(1);
  ASSERT_EQ(b_->frame(complete).hand_target, person_target(3));
  float pointing = -1.0f, gaze = -1.0f, at_user = -1.0f;
  run([&](std::size_t i, const RemotePeople& people, const Vec3& own_head) {
    if (i != complete) {
      return;
    }
    const presence::RemoteAvatar& b = *people.avatar(2);
    const Vec3 c_head = people.avatar(3)->eye_midpoint();
    pointing = angle_deg(b.index_fingertip() - b.eye_midpoint(), c_head - b.eye_midpoint());
    gaze = angle_deg(b.frame().deictic.gaze, c_head - b.frame().deictic.T_world_head.translation);
    // Not just anywhere ahead: A's user, the other person B's avatar could be taken to address.
    at_user = angle_deg(b.index_fingertip() - b.eye_midpoint(), own_head - b.eye_midpoint());
    EXPECT_EQ(b.stats().unknown_targets, 0u);
  });
  std::printf("B points at C in room A: avatar ray %.1f° off C's avatar's eyes, gaze %.1f°\n",
              static_cast<double>(pointing), static_cast<double>(gaze));
  EXPECT_GE(pointing, 0.0f);
  EXPECT_LT(pointing, 8.0f);
  EXPECT_LT(gaze, 8.0f);
  EXPECT_GT(at_user, 20.0f);
}

TEST_F(PeopleAsTargets, BLookingAtAsUserTurnsBsAvatarToAsUsersHead) {
  const std::size_t complete = b_->completion(0);
  ASSERT_EQ(b_->frame(complete).head_target, person_target(1));
  float gaze = -1.0f;
  run([&](std::size_t i, const RemotePeople& people, const Vec3& own_head) {
    if (i == complete) {
      const presence::RemoteAvatar& b = *people.avatar(2);
      gaze =
          angle_deg(b.frame().deictic.gaze, own_head - b.frame().deictic.T_world_head.translation);
    }
  });
  std::printf("B looks at A's user: avatar gaze %.1f° off their head\n", static_cast<double>(gaze));
  EXPECT_GE(gaze, 0.0f);
  EXPECT_LT(gaze, 8.0f);
}

TEST_F(PeopleAsTargets, GazesHeldOnPeopleAreRecordedForSessionJson) {
  const std::vector<PersonRecord> records =
      run([](std::size_t, const RemotePeople&, const Vec3&) {}, RemotePeopleOptions{64});
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].site, "B");
  EXPECT_EQ(records[0].frames_played, b_->frames());
  EXPECT_EQ(records[0].visible_ticks, b_->frames());
  double at_a = -1.0, at_c = -1.0;
  for (const GazeSample& g : records[0].gazes) {
    at_a = g.target == person_target(1) ? g.error_deg : at_a;
    at_c = g.target == person_target(3) ? g.error_deg : at_c;
  }
  std::printf("B's held gazes in room A: at A's user %.1f°, at C's avatar %.1f°\n", at_a, at_c);
  EXPECT_GE(at_a, 0.0);
  EXPECT_LT(at_a, 8.0);
  EXPECT_GE(at_c, 0.0);
  EXPECT_LT(at_c, 8.0);
  // C rested: their gaze on B's avatar (target 0 of C's room: "the other person", here A's user).
  EXPECT_EQ(records[1].site, "C");
}

// X (site A's user, capture subject `subject`) looks at B, at C, then at an object, over and
// over; C rests. In room B, X (person 2) stands on the first spot and C (person 3) on the second:
// X's avatar's gaze error at each hold on C's avatar, as session.json records them. From the
// first spot C is 61° to the left of the avatar's facing, while X's user turned 34° to their
// right (the spots of A and B are alike); `mirrored`: both rooms' spots mirrored (61° right, 34°
// left). tests/app/rooms_lifecycle_test.cpp measures the same with real processes.
struct HeldGazes {
  std::vector<double> settled;  // the gaze the avatar's eyes were given (presence/gaze_settle.h)
  std::vector<double> network;  // the networks' own gaze
};
HeldGazes gazes_at_c_in_room_b(const char* subject, bool mirrored,
                               const RemotePeopleOptions& options) {
  ScriptStep at_b = step(Action::kLookAt, script_person_target(0), 2.5f);
  at_b.person = "B";
  ScriptStep at_c = step(Action::kLookAt, script_person_target(1), 1.5f);
  at_c.person = "C";
  const Performer x("a.json", {at_b, at_c, step(Action::kLookAt, 1, 0.5f)}, {"B", "C"}, {1, 3},
                    14.0, subject, mirrored);
  const Performer c("c.json", rest(1.0f), {}, {}, static_cast<double>(x.frames()) / 30.0);
  const SiteConfig b = with_spots(site_config("b.json"), mirrored);
  RemotePeople people(b, shared().networks, shared().solver, options);
  people.meet(2, hello("A", x.body()));
  people.meet(3, hello("C", c.body()));
  const Vec3 own_head(0.0f, 1.62f, 0.0f);
  for (std::size_t i = 0; i < x.frames(); ++i) {
    LocalTargets room{&b.target_map, own_head};
    room.people = people.people_targets(1, own_head);
    const std::array<PersonFrame, 2> frames = {PersonFrame{2, &x.frame(i)},
                                               PersonFrame{3, &c.frame(i)}};
    people.tick(frames, room);
    people.end_tick();
  }
  people.finish();
  HeldGazes errors;
  std::printf(
      "subject %s (%s weights) looks at C in room B%s: off by", subject,
      options.left_hand_weights ? "own hand's" : "right-hand, on the mirror image if left-handed",
      mirrored ? ", spots mirrored" : "");
  const std::vector<PersonRecord> records = people.records();
  for (const GazeSample& g : records.at(0).gazes) {
    if (g.target == person_target(3)) {
      errors.settled.push_back(g.error_deg);
      errors.network.push_back(g.network_error_deg);
      std::printf(" %.1f° (networks %.1f°)", g.error_deg, g.network_error_deg);
    }
  }
  std::printf("\n");
  return errors;
}

double worst(const std::vector<double>& v) {
  return v.empty() ? 1e9 : *std::max_element(v.begin(), v.end());
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 1e9 : v[v.size() / 2];
}

// A left-handed person (subject 173) looking at a person lands as a right-handed one (172) does
// in the mirror layout: the networks' median hold within 1.5° of theirs, every hold within the 8°
// this file holds the networks' gaze at a person to (the right-handed person's own are 2.2–3.2°
// here and 7.5–8.0° in the mirror layout), since both go through the right-hand weights
// (docs/decisions.md §68). The left-hand weights as they are miss by 28° where the avatar turns
// the other way from its user: the finding that decision records. With gaze settling (decision
// 70), every hold of both people in both layouts is within the 5°, and settling a gaze
// 28° off turns it by its 15° bound only.
TEST(RemotePeople, ALeftHandedPersonsGazeAtAPersonLandsAsARightHandedPersonsDoes) {
  RemotePeopleOptions options{64};
  const HeldGazes right[2] = {gazes_at_c_in_room_b("172", false, options),
                              gazes_at_c_in_room_b("172", true, options)};
  for (const bool mirrored : {false, true}) {
    SCOPED_TRACE(mirrored ? "spots mirrored" : "spots as they are");
    const HeldGazes left = gazes_at_c_in_room_b("173", mirrored, options);
    ASSERT_GE(left.network.size(), 3u);
    ASSERT_GE(right[mirrored ? 1 : 0].settled.size(), 3u);
    EXPECT_LT(worst(left.network), 8.0);
    EXPECT_NEAR(median(left.network), median(right[mirrored ? 0 : 1].network), 1.5);
    EXPECT_LE(worst(left.settled), 5.0);
    EXPECT_LE(worst(right[mirrored ? 1 : 0].settled), 5.0);
  }
  options.left_hand_weights = true;
  const HeldGazes own = gazes_at_c_in_room_b("173", false, options);
  EXPECT_GT(worst(own.network), 20.0);
  for (std::size_t i = 0; i < own.settled.size(); ++i) {
    EXPECT_NEAR(own.settled[i], own.network[i] - 15.0, 0.5);
  }
}

TEST(RemotePeople, APersonTargetNobodyHereIsIsCountedAndCopied) {
  Performer b("b.json", rest(2.0f), {}, {});
  const SiteConfig a = site_config("a.json");
  RemotePeople people(a, shared().networks, shared().solver);
  people.meet(2, hello("B", b.body()));
  for (std::size_t i = 0; i < 30; ++i) {
    TrackingFrame f = b.frame(i);
    f.head_target = person_target(77);  // not in this room
    LocalTargets room{&a.target_map, Vec3(0, 1.6f, 0)};
    room.people = people.people_targets(1, room.partner_head);
    EXPECT_TRUE(people.play(PersonFrame{2, &f}, room));
    people.end_tick();
  }
  const presence::RemoteAvatar& avatar = *people.avatar(2);
  EXPECT_TRUE(avatar.visible());
  EXPECT_EQ(avatar.stats().unknown_targets, 30u);
  EXPECT_EQ(avatar.stats().held, 0u);
  EXPECT_TRUE(avatar.eye_midpoint().allFinite());
  EXPECT_FALSE(people.play(PersonFrame{5, &b.frame(0)}, LocalTargets{&a.target_map}));
}

// Three people in a room of three spots; person 2's frames stop for two seconds. Persons 1 and 3
// are exactly as in a run where nobody's frames stopped; person 2's avatar holds, is counted,
// and stays shown.
TEST(RemotePeople, OnePersonsMissingFramesAffectOnlyTheirAvatar) {
  SiteConfig c = site_config("c.json");
  c.spots.push_back(Placement{Vec3(1.3f, 0.0f, -1.4f), 140.0f});
  const std::vector<ScriptStep> pointing = {step(Action::kPoint, 1, 1.0f),
                                            step(Action::kPoint, 3, 1.0f)};
  const Performer performers[] = {Performer("a.json", pointing, {}, {}),
                                  Performer("b.json", pointing, {}, {}),
                                  Performer("c.json", pointing, {}, {})};
  const auto run = [&](bool lose) {
    RemotePeople people(c, shared().networks, shared().solver);
    for (PersonId id = 1; id <= 3; ++id) {
      people.meet(
          id, hello(std::string(1, static_cast<char>('A' + id - 1)), performers[id - 1].body()));
    }
    std::vector<std::array<Vec3, 3>> tips;
    for (std::size_t i = 0; i < 120; ++i) {
      LocalTargets room{&c.target_map, Vec3(0, 1.6f, 0)};
      room.people = people.people_targets(4, room.partner_head);
      std::array<PersonFrame, 3> frames;
      for (PersonId id = 1; id <= 3; ++id) {
        const bool lost = lose && id == 2 && i >= 30 && i < 90;
        frames[id - 1] = PersonFrame{id, lost ? nullptr : &performers[id - 1].frame(i)};
      }
      people.tick(frames, room);
      people.end_tick();
      EXPECT_EQ(people.visible().size(), 3u);
      tips.push_back({people.avatar(1)->index_fingertip(), people.avatar(2)->index_fingertip(),
                      people.avatar(3)->index_fingertip()});
    }
    if (lose) {
      EXPECT_EQ(people.stats(2)->frames_missed, 60u);
      EXPECT_EQ(people.avatar(2)->stats().held, 60u);
      EXPECT_EQ(people.stats(1)->frames_missed, 0u);
      EXPECT_EQ(people.stats(3)->frames_missed, 0u);
      EXPECT_EQ(people.stats(2)->visible_ticks, 120u);
    }
    return tips;
  };
  const auto whole = run(false);
  const auto lossy = run(true);
  std::size_t differs = 0;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(whole[i][0], lossy[i][0]) << "tick " << i;
    EXPECT_EQ(whole[i][2], lossy[i][2]) << "tick " << i;
    differs += whole[i][1] != lossy[i][1] ? 1 : 0;
  }
  EXPECT_GT(differs, 30u);  // person 2 held still while their hand was moving
}

// tick() runs the networks batched across people (presence::tick_people): the avatars end where
// playing each person alone puts them, within 1e-5 m; a person given twice in one tick plays
// both frames in order, as two plays would.
TEST(RemotePeople, ABatchedTickIsPlayingEachPersonAlone) {
  const SiteConfig c = site_config("c.json");
  const std::vector<ScriptStep> pointing = {step(Action::kPoint, 1, 0.5f)};
  const Performer a("a.json", pointing, {}, {});
  const Performer b("b.json", pointing, {}, {});
  RemotePeople batched(c, shared().networks, shared().solver);
  RemotePeople alone(c, shared().networks, shared().solver);
  for (RemotePeople* people : {&batched, &alone}) {
    people->meet(1, hello("A", a.body()));
    people->meet(2, hello("B", b.body()));
  }
  const LocalTargets room{&c.target_map, Vec3(0, 1.6f, 0)};
  float worst = 0.0f;
  for (std::size_t i = 0; i < 60; i += 2) {
    // Person 2 twice (a late loop catching up), person 1 once, then missed.
    const std::array<PersonFrame, 4> frames = {
        PersonFrame{2, &b.frame(i)}, PersonFrame{1, &a.frame(i)}, PersonFrame{2, &b.frame(i + 1)},
        PersonFrame{1, nullptr}};
    batched.tick(frames, room);
    for (const PersonFrame& f : frames) {
      alone.play(f, room);
    }
    for (PersonId id : {PersonId{1}, PersonId{2}}) {
      worst = std::max(
          {worst,
           (batched.avatar(id)->index_fingertip() - alone.avatar(id)->index_fingertip()).norm(),
           (batched.avatar(id)->eye_midpoint() - alone.avatar(id)->eye_midpoint()).norm()});
    }
  }
  EXPECT_LT(worst, 1e-5f);
  EXPECT_EQ(batched.stats(2)->frames_played, 60u);
  EXPECT_EQ(batched.stats(1)->frames_played, 30u);
  EXPECT_EQ(batched.stats(1)->frames_missed, 30u);
  EXPECT_EQ(batched.avatar(2)->stats().ticks, alone.avatar(2)->stats().ticks);
}

TEST(RemotePeople, ScriptedPeopleResolveToWhoeverOfThatSiteIsHere) {
  const SiteConfig a = site_config("a.json");
  RemotePeople people(a, shared().networks, shared().solver);
  people.meet(6, hello("B"));
  const std::vector<std::string> names = {"C", "B"};
  TrackingFrame f;
  f.head_target = script_person_target(1);  // B
  f.hand_target = script_person_target(0);  // C: not here
  EXPECT_EQ(resolve_script_people(f, names, people), 1);
  EXPECT_EQ(f.head_target, person_target(6));
  EXPECT_EQ(f.hand_target, kNoTarget);
  // Objects and the other person are left alone; a direct session's person is the other person.
  TrackingFrame g;
  g.head_target = 4;
  g.hand_target = script_person_target(1);
  EXPECT_EQ(resolve_script_people(g, names, people, true), 0);
  EXPECT_EQ(g.head_target, 4);
  EXPECT_EQ(g.hand_target, kPartnerTarget);
  // An index the script never named (a corrupt frame) targets nothing, counted.
  TrackingFrame h;
  h.head_target = script_person_target(9);
  h.hand_target = 2;
  EXPECT_EQ(resolve_script_people(h, names, people), 1);
  EXPECT_EQ(h.head_target, kNoTarget);
}

// Avatars fade rather than pop (decision 84): a person's avatar fades in over kFadeInTicks once
// posed; when their stream stops it stays drawn, holding its last pose, fading out over
// kFadeOutTicks; when it comes back it fades in again. A person who leaves fades out where they
// stood; a newcomer on that spot replaces the fading avatar and fades in from nothing.
TEST(RemotePeople, AvatarsFadeInAndOutRatherThanPopping) {
  const SiteConfig a = site_config("a.json");
  const Performer b("b.json", {step(Action::kPoint, 1, 1.0f)}, {}, {});
  RemotePeople people(a, shared().networks, shared().solver);
  people.meet(1, hello("B", b.body()));
  const LocalTargets room{&a.target_map, Vec3(0, 1.6f, 0)};
  std::size_t i = 0;
  const auto tick = [&](bool streaming) {  // a stopped stream plays nothing
    if (streaming) {
      people.play(PersonFrame{1, &b.frame(i++)}, room);
    }
    people.end_tick();
  };
  const auto opacity = [&] { return people.drawn().empty() ? 0.0f : people.drawn()[0].opacity; };
  EXPECT_TRUE(people.drawn().empty()) << "not posed yet";
  for (int k = 1; k <= RemotePeople::kFadeInTicks; ++k) {
    tick(true);
    ASSERT_EQ(people.visible().size(), 1u);
    EXPECT_FLOAT_EQ(opacity(), static_cast<float>(k) / RemotePeople::kFadeInTicks) << k;
  }
  tick(true);
  EXPECT_EQ(opacity(), 1.0f);
  EXPECT_EQ(people.drawn()[0].avatar, people.avatar(1));
  EXPECT_EQ(people.drawn()[0].mesh, nullptr) << "the site's default avatar";

  // The stream stops: not live at once, drawn fading in its last pose.
  people.set_live(1, false);
  const Pose held = people.avatar(1)->T_world_model();
  const std::vector<Pose> held_joints(people.avatar(1)->model_pose().begin(),
                                      people.avatar(1)->model_pose().end());
  for (int k = RemotePeople::kFadeOutTicks - 1; k >= 1; --k) {
    tick(false);
    EXPECT_TRUE(people.visible().empty());
    ASSERT_EQ(people.drawn().size(), 1u) << k;
    EXPECT_NEAR(opacity(), static_cast<float>(k) / RemotePeople::kFadeOutTicks, 1e-6f) << k;
    EXPECT_TRUE(people.drawn()[0].avatar->T_world_model().translation.isApprox(held.translation));
  }
  EXPECT_TRUE(
      std::equal(held_joints.begin(), held_joints.end(), people.avatar(1)->model_pose().begin(),
                 [](const Pose& x, const Pose& y) { return x.translation == y.translation; }))
      << "held where it was";
  tick(false);
  EXPECT_TRUE(people.drawn().empty()) << "faded out";

  // Back: fades in again.
  people.set_live(1, true);
  tick(true);
  EXPECT_FLOAT_EQ(opacity(), 1.0f / RemotePeople::kFadeInTicks);
  for (int k = 0; k < RemotePeople::kFadeInTicks; ++k) {
    tick(true);
  }
  EXPECT_EQ(opacity(), 1.0f);

  // Leaving: the spot is free and the avatar fades out where it stood.
  const presence::RemoteAvatar* leaving = people.avatar(1);
  people.leave(1);
  EXPECT_EQ(people.avatar(1), nullptr);
  EXPECT_EQ(people.size(), 0u);
  people.end_tick();
  ASSERT_EQ(people.drawn().size(), 1u);
  EXPECT_EQ(people.drawn()[0].avatar, leaving);
  EXPECT_LT(opacity(), 1.0f);
  people.end_tick();
  // A newcomer takes the spot before the fade ends: the fading avatar goes, theirs fades in.
  people.meet(2, hello("C", b.body()));
  EXPECT_EQ(people.stats(2)->spot, 0u);
  EXPECT_TRUE(people.drawn().empty()) << "the newcomer is not posed yet";
  people.play(PersonFrame{2, &b.frame(0)}, room);
  people.end_tick();
  ASSERT_EQ(people.drawn().size(), 1u);
  EXPECT_EQ(people.drawn()[0].avatar, people.avatar(2));
  EXPECT_FLOAT_EQ(opacity(), 1.0f / RemotePeople::kFadeInTicks);
  // And when nobody comes, a departed person's avatar is let go once faded out.
  people.leave(2);
  for (int k = 0; k < RemotePeople::kFadeOutTicks; ++k) {
    people.end_tick();
  }
  EXPECT_TRUE(people.drawn().empty());
}

TEST(RemotePeople, RecordsSumAPersonsStaysBySite) {
  Performer b("b.json", rest(1.0f), {}, {});
  const SiteConfig a = site_config("a.json");
  RemotePeople people(a, shared().networks, shared().solver);
  const auto play = [&](PersonId id, std::size_t ticks) {
    for (std::size_t i = 0; i < ticks; ++i) {
      people.play(PersonFrame{id, i % 5 == 4 ? nullptr : &b.frame(i)},
                  LocalTargets{&a.target_map, Vec3(0, 1.6f, 0)});
      people.end_tick();
    }
  };
  people.meet(2, hello("B", b.body()));
  play(2, 10);
  people.leave(2);
  people.meet(9, hello("B", b.body()));  // back, with a fresh id
  play(9, 5);
  people.meet(4, hello("C", b.body()));
  const std::vector<PersonRecord> records = people.records();
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0].site, "B");
  EXPECT_EQ(records[0].stays, 2u);
  EXPECT_EQ(records[0].frames_played, 12u);
  EXPECT_EQ(records[0].frames_missed, 3u);
  EXPECT_EQ(records[0].visible_ticks, 15u);
  EXPECT_EQ(records[1].site, "C");
  EXPECT_EQ(records[1].frames_played, 0u);
}

TEST(SessionReport, PeopleHaveOneEntryEachWithNullErrorsWhenNoneWasObserved) {
  SiteRecord r;
  r.site = "A";
  PersonRecord b;
  b.site = "B";
  b.frames_played = 240;
  b.visible_ticks = 239;
  eval::DeicticSample s;
  s.avatar.horizontal_deg = 2.0;
  s.avatar.vertical_deg = 1.0;
  b.completions = {s, s};
  b.completions[1].avatar.horizontal_deg = 4.0;
  b.gazes = {GazeSample{person_target(3), 2.0}, GazeSample{4, 4.0}};
  PersonRecord c;
  c.site = "C";
  c.frames_played = 7;
  r.people = {b, c};
  const fs::path path = fs::path(::testing::TempDir()) / "people_session.json";
  write_site_report(r, path);
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
  ASSERT_EQ(j["people"].size(), 2u);
  EXPECT_EQ(j["people"][0]["site"], "B");
  EXPECT_EQ(j["people"][0]["frames_played"], 240);
  EXPECT_EQ(j["people"][0]["visible_ticks"], 239);
  EXPECT_DOUBLE_EQ(j["people"][0]["he_deg"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["people"][0]["ve_deg"].get<double>(), 1.0);
  EXPECT_EQ(j["people"][1]["site"], "C");
  EXPECT_TRUE(j["people"][1]["he_deg"].is_null());
  EXPECT_TRUE(j["people"][1]["ve_deg"].is_null());
  EXPECT_DOUBLE_EQ(j["people"][0]["gaze_deg"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["people"][0]["gaze_at_people_deg"].get<double>(), 2.0);
  EXPECT_EQ(j["people"][0]["gazes"].size(), 2u);
  EXPECT_EQ(j["people"][0]["gazes"][0]["target"], person_target(3));
  EXPECT_TRUE(j["people"][1]["gaze_deg"].is_null());
  EXPECT_TRUE(j.contains("avatar_visible_ticks"));  // the existing fields stay
  EXPECT_TRUE(j.contains("pointing"));
}

}  // namespace
}  // namespace deixis::site
