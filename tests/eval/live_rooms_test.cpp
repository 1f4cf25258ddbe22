// The live evaluation's generated rooms keep to their stated rules and are sites the runtime
// reads; its statistics are the textbook ones (eval/room_pairs.h, eval/live_rooms.h).

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/math/angles.h"
#include "eval/live_rooms.h"
#include "eval/room_pairs.h"
#include "eval/room_rules_file.h"
#include "site/site_config.h"
#include "test_support.h"

namespace deixis::eval {
namespace {

namespace fs = std::filesystem;

const ScriptedPerson kRight{"172", Hand::kRight};
const ScriptedPerson kLeft{"173", Hand::kLeft};

float horizontal(const Vec3& v) {
  return std::hypot(v.x(), v.z());
}

const RoomObject& object(const GeneratedRoom& room, TargetId id) {
  for (const RoomObject& o : room.objects) {
    if (o.id == id) {
      return o;
    }
  }
  throw std::runtime_error("no object " + std::to_string(id));
}

TEST(RoomPairs, TheSameSeedAndIndexGiveTheSamePairAndOthersDiffer) {
  const RoomRules rules;
  const RoomPair a = generate_room_pair(rules, 7, 3, kRight, kLeft);
  const RoomPair again = generate_room_pair(rules, 7, 3, kRight, kLeft);
  const RoomPair next = generate_room_pair(rules, 7, 4, kRight, kLeft);
  const RoomPair other_seed = generate_room_pair(rules, 8, 3, kRight, kLeft);
  for (std::size_t r = 0; r < 2; ++r) {
    ASSERT_EQ(a.rooms[r].objects.size(), again.rooms[r].objects.size());
    for (std::size_t k = 0; k < a.rooms[r].objects.size(); ++k) {
      EXPECT_EQ(a.rooms[r].objects[k].position, again.rooms[r].objects[k].position);
    }
    EXPECT_NE(a.rooms[r].objects[0].position, next.rooms[r].objects[0].position);
    EXPECT_NE(a.rooms[r].objects[0].position, other_seed.rooms[r].objects[0].position);
  }
  // The same object stands elsewhere in the other room: what the translation is for.
  EXPECT_GT((object(a.rooms[0], 1).position - object(a.rooms[1], 1).position).norm(), 0.05f);
}

void expect_rooms_keep_to(const RoomRules& rules) {
  for (int index = 0; index < 200; ++index) {
    SCOPED_TRACE(index);
    const RoomPair pair = generate_room_pair(rules, 11, index, kRight, kLeft);
    for (std::size_t r = 0; r < 2; ++r) {
      const GeneratedRoom& room = pair.rooms[r];
      const float d = room.spot_distance;
      EXPECT_GE(d, rules.spot_distance_min);
      EXPECT_LE(d, rules.spot_distance_max);
      bool left = false, right = false;
      for (const TargetId id : kPointTargets) {
        const Vec3 p = object(room, id).position;
        EXPECT_GE(horizontal(p), rules.point_distance_min - 1e-4f);
        EXPECT_LE(horizontal(p), rules.point_distance_max + 1e-4f);
        EXPECT_GE(p.y(), rules.point_height_min);
        EXPECT_LE(p.y(), rules.point_height_max);
        // Between the user and the avatar, to the side.
        EXPECT_LE(p.z(), -rules.between_margin + 1e-4f);
        EXPECT_GE(p.z(), -(d - rules.between_margin) - 1e-4f);
        EXPECT_GE(std::atan2(std::abs(p.x()), -p.z()) * kDegPerRad,
                  rules.point_azimuth_min_deg - 1e-2f);
        left = left || p.x() < 0.0f;
        right = right || p.x() > 0.0f;
      }
      EXPECT_TRUE(left && right) << "targets on one side only";
      // The user's touch target is near the user on their deictic side, the other person's near
      // the avatar's spot on that person's side (the avatar faces +Z: its right is −X).
      const Hand user_hand = room.user.hand;
      const Hand remote_hand = pair.rooms[1 - r].user.hand;
      const Vec3 own = object(room, room.own_touch).position;
      const Vec3 theirs =
          object(room, room.own_touch == kTouchOfA ? kTouchOfB : kTouchOfA).position;
      EXPECT_LE(horizontal(own), std::hypot(rules.touch_side_max, rules.touch_forward_max) + 1e-4f);
      EXPECT_EQ(own.x() > 0.0f, user_hand == Hand::kRight);
      EXPECT_LT(own.z(), 0.0f);
      const Vec3 from_spot = theirs - Vec3(0.0f, 0.0f, -d);
      EXPECT_LE(horizontal(from_spot),
                std::hypot(rules.touch_side_max, rules.touch_forward_max) + 1e-4f);
      EXPECT_EQ(theirs.x() < 0.0f, remote_hand == Hand::kRight);
      EXPECT_GT(from_spot.z(), 0.0f);
      for (const Vec3& t : {own, theirs}) {
        EXPECT_GE(t.y(), rules.touch_height_min);
        EXPECT_LE(t.y(), rules.touch_height_max);
      }
    }
  }
}

TEST(RoomPairs, EveryRoomKeepsToTheRules) {
  expect_rooms_keep_to(RoomRules{});
}

fs::path write_rules(const deixis::testing::ScratchDir& dir, const std::string& text) {
  const fs::path file = dir.path() / "rules.json";
  std::ofstream(file) << text;
  return file;
}

// Other rules from a file (`--rules`): the fields given replace the defaults, the rest stay, and
// the rooms keep to them; what a report prints reads back as the same rules.
TEST(RoomRulesFile, TheFieldsGivenReplaceTheDefaultsAndTheRoomsKeepToThem) {
  deixis::testing::ScratchDir dir;
  const RoomRules low = read_room_rules(write_rules(dir, R"({"format": "deixis-room-rules",
      "version": 1, "point_height": [0.9, 1.1], "spot_distance": [2.4, 3.0],
      "point_azimuth_min_deg": 35, "touch_height": [0.9, 1.0]})"));
  EXPECT_EQ(low.point_height_min, 0.9f);
  EXPECT_EQ(low.point_height_max, 1.1f);
  EXPECT_EQ(low.spot_distance_min, 2.4f);
  EXPECT_EQ(low.point_azimuth_min_deg, 35.0f);
  EXPECT_EQ(low.touch_height_max, 1.0f);
  EXPECT_EQ(low.point_distance_max, RoomRules{}.point_distance_max);  // not given: the default
  expect_rooms_keep_to(low);
  const RoomRules again = read_room_rules(write_rules(dir, room_rules_json(low)));
  EXPECT_EQ(room_rules_json(again), room_rules_json(low));
  EXPECT_EQ(again.point_height_max, 1.1f);
}

TEST(RoomRulesFile, BadFilesAreRefusedNamingTheFileAndTheField) {
  deixis::testing::ScratchDir dir;
  const std::string head = R"({"format": "deixis-room-rules", "version": 1, )";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + R"("point_hieght": [1, 2]})", "unknown field 'point_hieght'"},
      {head + R"("point_height": [1, "2"]})", "point_height[1]: not a number"},
      {head + R"("point_height": [1]})", "point_height: expected [min, max]"},
      {head + R"("point_height": [2, 1]})", "point_height: minimum above maximum"},
      {head + R"("point_distance": [1, 1e9]})", "point_distance[1]: 1000000000.0 is outside"},
      {head + R"("between_margin": -0.1})", "between_margin: -0.1 is outside"},
      {head + R"("min_separation": null})", "min_separation: not a number"},
      {R"({"format": "deixis-target-map", "version": 1})", "deixis-room-rules"},
      {R"({"format": "deixis-room-rules", "version": 2})", "\"version\": 1"},
      {R"({"format": 18444073709103232, "version": 1})", "deixis-room-rules"},  // fuzz-found
      {R"({"format": "deixis-room-rules", "version": "1"})", "\"version\": 1"},
      {"[1, 2", "not a JSON object"},
      {std::string(70 * 1024, ' ') + "{}", "larger than 65536 bytes"},
  };
  for (const auto& [text, named] : cases) {
    const fs::path file = write_rules(dir, text);
    try {
      read_room_rules(file);
      ADD_FAILURE() << "accepted: " << text.substr(0, 100);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(read_room_rules(dir.path() / "missing.json"), Error);
}

TEST(RoomPairs, RulesThatLeaveNoRoomAreRefusedNamingTheRule) {
  RoomRules rules;
  rules.point_height_min = 3.0f;
  try {
    generate_room_pair(rules, 1, 0, kRight, kRight);
    FAIL() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point height"), std::string::npos) << e.what();
  }
}

TEST(RoomPairs, TheWrittenSitesAreReadByTheRuntime) {
  deixis::testing::ScratchDir dir;
  const RoomPair pair = generate_room_pair(RoomRules{}, 5, 0, kRight, kLeft);
  const fs::path avatar = deixis::testing::source_dir() / "assets/avatars/default.glb";
  write_room_pair(pair, avatar, dir.path());
  for (std::size_t r = 0; r < 2; ++r) {
    const GeneratedRoom& room = pair.rooms[r];
    const site::SiteConfig config =
        site::read_site_config(dir.path() / (r == 0 ? "a.json" : "b.json"));
    EXPECT_EQ(config.site, room.site);
    ASSERT_TRUE(config.virtual_user.has_value());
    EXPECT_EQ(config.virtual_user->subject, room.user.subject);
    EXPECT_EQ(config.target_map.objects.size(), room.objects.size());
    for (const RoomObject& o : room.objects) {
      const TargetObject* read = config.target_map.find(o.id);
      ASSERT_NE(read, nullptr) << o.id;
      EXPECT_LT((read->position - o.position).norm(), 1e-3f) << o.id;  // written in mm
    }
    EXPECT_LT(
        (config.remote_avatar.T_world_floor().translation - Vec3(0.0f, 0.0f, -room.spot_distance))
            .norm(),
        1e-3f);
    // The script points at the three targets and touches the user's own one.
    int points = 0, touches = 0;
    for (const ScriptStep& s : config.virtual_user->script) {
      points += s.action == ScriptStep::Action::kPoint ? 1 : 0;
      if (s.action == ScriptStep::Action::kTouch) {
        ++touches;
        EXPECT_EQ(s.target, room.own_touch);
      }
    }
    EXPECT_EQ(points, 3);
    EXPECT_EQ(touches, 1);
  }
}

TEST(RoomPairs, GeometryIsSeenFromTheAvatarsShoulder) {
  GeneratedRoom room;
  room.spot_distance = 2.0f;
  // Straight ahead of the avatar (toward the user, +Z) at shoulder height.
  TargetGeometry g = geometry_from_avatar(room, Vec3(0.0f, kAvatarShoulderHeight, 0.0f));
  EXPECT_NEAR(g.distance, 2.0f, 1e-5f);
  EXPECT_NEAR(g.elevation_deg, 0.0f, 1e-4f);
  EXPECT_NEAR(g.azimuth_deg, 0.0f, 1e-4f);
  // To the avatar's right (−X), one metre up over one metre: +90° azimuth, 45° elevation.
  g = geometry_from_avatar(room, Vec3(-1.0f, kAvatarShoulderHeight + 1.0f, -2.0f));
  EXPECT_NEAR(g.azimuth_deg, 90.0f, 1e-3f);
  EXPECT_NEAR(g.elevation_deg, 45.0f, 1e-3f);
  // Behind it.
  g = geometry_from_avatar(room, Vec3(0.0f, kAvatarShoulderHeight, -3.0f));
  EXPECT_NEAR(std::abs(g.azimuth_deg), 180.0f, 1e-3f);
}

TEST(LiveRooms, DistributionsAreMeanMedianNinetiethPercentileAndWorst) {
  std::vector<double> values;
  for (int i = 10; i >= 1; --i) {
    values.push_back(i);
  }
  values.push_back(std::numeric_limits<double>::quiet_NaN());  // a missing value is left out
  const Distribution d = distribution(values);
  EXPECT_EQ(d.count, 10u);
  EXPECT_DOUBLE_EQ(d.mean, 5.5);
  EXPECT_DOUBLE_EQ(d.median, 5.5);
  EXPECT_NEAR(d.p90, 9.1, 1e-12);  // numpy.percentile(range(1, 11), 90)
  EXPECT_DOUBLE_EQ(d.worst, 10.0);
  const Distribution none = distribution({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_TRUE(std::isnan(none.mean));
  EXPECT_TRUE(std::isnan(none.worst));
}

TEST(LiveRooms, TheSummaryGroupsPointingAndTouchingAndTalliesTouches) {
  const auto point = [](const char* subject, double he, double ve, float elevation, float azimuth) {
    LiveCompletion c;
    c.subject = subject;
    c.avatar_he = he;
    c.avatar_ve = ve;
    c.copy_he = 10.0 * he;
    c.copy_ve = 10.0 * ve;
    c.avatar_cm = c.copy_cm = std::numeric_limits<double>::quiet_NaN();
    c.geometry = {2.0f, elevation, azimuth};
    return c;
  };
  LiveCompletion touch;
  touch.subject = "172";
  touch.touch = true;
  touch.avatar_cm = 0.8;
  touch.copy_cm = 12.0;
  touch.avatar_he = touch.avatar_ve = touch.copy_he = touch.copy_ve =
      std::numeric_limits<double>::quiet_NaN();
  const std::vector<LiveCompletion> completions = {point("172", 1.0, 2.0, 5.0f, 40.0f),
                                                   point("173", 3.0, 4.0, -20.0f, -100.0f), touch};
  const std::vector<TouchTally> touches = {{0, "A", "172", 1, 1}, {0, "B", "173", 1, 0}};
  const LiveSummary s = summarize(completions, touches, 1);
  EXPECT_EQ(s.all.he.count, 2u);
  EXPECT_DOUBLE_EQ(s.all.he.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.all.ve.worst, 4.0);
  EXPECT_DOUBLE_EQ(s.all.copy_he.mean, 20.0);
  EXPECT_EQ(s.all.touch_cm.count, 1u);
  EXPECT_DOUBLE_EQ(s.all.touch_cm.mean, 0.8);
  ASSERT_EQ(s.by_subject.size(), 2u);
  EXPECT_EQ(s.by_subject[0].label, "172");
  EXPECT_EQ(s.by_subject[0].touch_cm.count, 1u);
  ASSERT_EQ(s.by_azimuth.size(), 2u);  // 30–60° and behind; touches are not binned
  EXPECT_EQ(s.by_azimuth[1].label, "≥ 90° (behind)");
  EXPECT_DOUBLE_EQ(s.by_azimuth[1].he.mean, 3.0);
  EXPECT_EQ(s.touches_performed, 2);
  EXPECT_EQ(s.touches_observed, 1);
  const std::string md = live_rooms_markdown(s, "deixis eval --live-rooms 1");
  EXPECT_NE(md.find("Touches completed by the users: 2; observed as completed at the other "
                    "site: 1"),
            std::string::npos)
      << md;
}

}  // namespace
}  // namespace deixis::eval
