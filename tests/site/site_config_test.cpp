// Site configurations: the committed demo sites load; every kind of bad field is named.

#include "site/site_config.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "test_support.h"

namespace deixis::site {
namespace {

namespace fs = std::filesystem;

TEST(SiteConfig, TheDemoSitesLoad) {
  for (const char* name : {"a.json", "b.json", "c.json"}) {
    const SiteConfig site = read_site_config(testing::source_dir() / "assets/sites" / name);
    EXPECT_FALSE(site.target_map.objects.empty());
    ASSERT_TRUE(site.virtual_user.has_value());
    EXPECT_FALSE(site.virtual_user->script.empty());
    EXPECT_TRUE(fs::path(site.avatar_path).filename() == "default.glb");
    // The remote avatar faces the user: yaw 180 turns −Z into +Z.
    const Vec3 facing = site.remote_avatar.T_world_floor().rotation * Vec3(0, 0, -1);
    EXPECT_TRUE(facing.isApprox(Vec3(0, 0, 1), 1e-6f));
  }
}

std::string with(const std::string& replace, const std::string& by) {
  std::string text = R"({
    "format": "deixis-site", "version": 1, "site": "T", "target_map": "rooms/a.json",
    "user": { "floor": [0, 0, 0], "yaw_degrees": 0 },
    "remote_avatar": { "floor": [0, 0, -2], "yaw_degrees": 180, "avatar": "x.glb" },
    "virtual_user": { "subject": "172", "script": [ { "action": "point", "target": 1 } ] }
  })";
  const auto at = text.find(replace);
  if (at != std::string::npos) {
    text.replace(at, replace.size(), by);
  }
  return text;
}

TEST(SiteConfig, BadFieldsAreNamed) {
  const fs::path base = testing::source_dir() / "assets";
  const std::pair<std::string, std::string> cases[][1] = {
      {{"\"version\": 1", "\"version\": 2"}},
      {{"\"floor\": [0, 0, -2]", "\"floor\": [0, 0, \"x\"]"}},
      {{"\"yaw_degrees\": 180", "\"yaw_degrees\": 400"}},
      {{"\"action\": \"point\"", "\"action\": \"wave\""}},
      {{"\"target\": 1", "\"target\": 99"}},
      {{"\"site\": \"T\"", "\"site\": \"T\", \"colour\": 1"}},
      {{"rooms/a.json", "rooms/missing.json"}},
      {{"[ { \"action\": \"point\", \"target\": 1 } ]", "[]"}},
  };
  const char* expected[] = {"version: this Deixis reads version 1",
                            "remote_avatar.floor[2]: not a finite number",
                            "remote_avatar.yaw_degrees: expected a number in",
                            "virtual_user.script[0].action: unknown action 'wave'",
                            "virtual_user.script[0].target: no object with id 99",
                            ": unknown field 'colour'",
                            "target_map: ",
                            "virtual_user.script: expected an array of 1 to 1000 steps"};
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    const std::string text = with(cases[i][0].first, cases[i][0].second);
    try {
      parse_site_config(text, "sites/t.json", base);
      ADD_FAILURE() << "accepted case " << i;
    } catch (const deixis::Error& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind("sites/t.json: ", 0), 0u) << message;
      EXPECT_NE(message.find(expected[i]), std::string::npos) << message;
    }
  }
}

// A site configuration is a file from anywhere; each hostile class is a clear error.
TEST(SiteConfig, HostileFilesAreRefusedNamingFileAndPlace) {
  const fs::path base = testing::source_dir() / "assets";
  const std::string deep = std::string(80, '{') + std::string(80, '}');
  const std::pair<std::string, std::string> cases[] = {
      {with("\"site\": \"T\"", "\"site\": \"T\", \"camera\": " + deep),
       "sites/t.json: nested deeper than 64 levels"},
      {with("\"yaw_degrees\": 0", "\"yaw_degrees\": 0, \"yaw_degrees\": 90"),
       "sites/t.json: duplicate key 'yaw_degrees' in user"},
      {with("\"target\": 1", "\"target\": 1, \"target\": 2"),
       "sites/t.json: duplicate key 'target' in virtual_user.script[0]"},
      // 2^64 − 1: as int64 it is −1; 2^63 + 1 wraps below zero.
      {with("\"version\": 1", "\"version\": 18446744073709551615"),
       "sites/t.json: version: expected an integer from 0 to 1000"},
      {with("\"subject\": \"172\"", "\"subject\": \"172\", \"seed\": 9223372036854775809"),
       "sites/t.json: virtual_user.seed: expected an integer from 0 to"},
      {with("\"site\": \"T\"", "\"site\": \"T\\u001b[31m\""),
       "sites/t.json: site: not valid UTF-8 text without control characters"},
      {with("\"site\": \"T\"", "\"site\": \"" + std::string(65, 'T') + "\""),
       "sites/t.json: site: expected 1 to 64 bytes, found 65"},
      {with("\"site\": \"T\"", "\"site\": \"\""), "sites/t.json: site: expected 1 to 64 bytes"},
      {with("\"site\": \"T\"", "\"site\": \"\xff\""), "sites/t.json: not valid JSON"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_site_config(text, "sites/t.json", base);
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const deixis::Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

TEST(SiteConfig, TheDemoSitesHaveTwoSpotsInRoomsFurnishedDifferently) {
  std::vector<SiteConfig> sites;
  for (const char* name : {"a.json", "b.json", "c.json"}) {
    sites.push_back(read_site_config(testing::source_dir() / "assets/sites" / name));
    const SiteConfig& site = sites.back();
    ASSERT_EQ(site.spots.size(), 2u) << name;
    // The first spot is the direct session's avatar; every spot faces the user within 45°.
    EXPECT_TRUE(site.remote_avatar.floor.isApprox(site.spots[0].floor));
    for (const Placement& spot : site.spots) {
      const Vec3 facing = spot.T_world_floor().rotation * Vec3(0, 0, -1);
      const Vec3 to_user = (site.user.floor - spot.floor).normalized();
      EXPECT_GT(facing.dot(to_user), std::cos(45.0f * 3.14159265f / 180.0f)) << name;
    }
  }
  // The same object ids in every room, at other places.
  for (std::size_t i = 1; i < sites.size(); ++i) {
    ASSERT_EQ(sites[i].target_map.objects.size(), sites[0].target_map.objects.size());
    for (const TargetObject& object : sites[0].target_map.objects) {
      const TargetObject* there = sites[i].target_map.find(object.id);
      ASSERT_NE(there, nullptr);
      EXPECT_EQ(there->name, object.name);
      EXPECT_GT((there->position - object.position).norm(), 0.3f) << object.name;
    }
  }
}

const char kOneSpot[] =
    R"("remote_avatar": { "floor": [0, 0, -2], "yaw_degrees": 180, "avatar": "x.glb" })";

TEST(SiteConfig, ASpotListKeepsItsOrder) {
  const std::string text = with(kOneSpot, R"("remote_avatar": { "avatar": "x.glb", "spots": [
        { "floor": [0, 0, -2], "yaw_degrees": 180 }, { "floor": [1, 0, -1.5], "yaw_degrees": 150 },
        { "floor": [-1, 0, -1.5], "yaw_degrees": -150 } ] })");
  const SiteConfig site = parse_site_config(text, "sites/t.json", testing::source_dir() / "assets");
  ASSERT_EQ(site.spots.size(), 3u);
  EXPECT_TRUE(site.spots[1].floor.isApprox(Vec3(1, 0, -1.5f)));
  EXPECT_FLOAT_EQ(site.spots[2].yaw_degrees, -150.0f);
  EXPECT_TRUE(site.remote_avatar.floor.isApprox(Vec3(0, 0, -2)));
  EXPECT_EQ(site.avatar_path.filename(), "x.glb");
  // The one-spot form is a list of one.
  EXPECT_EQ(parse_site_config(with("", ""), "sites/t.json", testing::source_dir() / "assets")
                .spots.size(),
            1u);
}

// A spot facing +Z (toward the user at the origin) at z = −2: an object at z = −4 stands behind
// it, one at z = 0 in front of it; a second spot to its left, turned 20° toward it, is 82° off
// and sees the first 78° to its right: both within reach. Directions are the avatar's: facing
// +Z, its left is +X.
TEST(SiteConfig, TargetsBehindASpotAreFoundWithTheirSide) {
  const std::string text = with(kOneSpot, R"("remote_avatar": { "avatar": "x.glb", "spots": [
        { "floor": [0, 0, -2], "yaw_degrees": 180 }, { "floor": [1.5, 0, -1.8], "yaw_degrees": 160 } ] })");
  SiteConfig site = parse_site_config(text, "sites/t.json", testing::source_dir() / "assets");
  site.target_map.objects = {
      {7, "Lamp", TargetKind::kSphere, Vec3(-0.5f, 1.5f, -4.0f), Vec3::Constant(0.2f)},
      {8, "Mug", TargetKind::kSphere, Vec3(0.0f, 1.0f, 0.0f), Vec3::Constant(0.1f)}};
  const std::vector<BehindSpot> behind = behind_spots(site);
  // Spot 1: the lamp, 166° to its right (−X is the avatar's right); spot 2: the lamp, 118° to its
  // right. Nothing else: the mug, the user and the other spot are within 90°.
  ASSERT_EQ(behind.size(), 2u);
  EXPECT_EQ(behind[0].spot, 0u);
  EXPECT_EQ(behind[0].what, "Lamp (id 7)");
  EXPECT_NEAR(behind[0].azimuth_degrees, -(180.0f - std::atan2(0.5f, 2.0f) * 57.29578f), 0.01f);
  EXPECT_EQ(behind[1].spot, 1u);
  EXPECT_NEAR(behind[1].azimuth_degrees, -117.726f, 0.01f);
  EXPECT_EQ(describe(site, behind[0]),
            "sites/t.json: Lamp (id 7) stands 166° to the right of where avatar spot 1 faces: an "
            "avatar there turns its body away from the room to look or point at it "
            "(docs/site-config.md)");
}

TEST(SiteConfig, RoomAsTvStandsBehindItsFirstSpot) {
  // The demo's room A (docs/demo.md): its TV stands 139° from where the first spot faces.
  const SiteConfig a = read_site_config(testing::source_dir() / "assets/sites/a.json");
  bool tv_behind_first = false;
  for (const BehindSpot& b : behind_spots(a)) {
    tv_behind_first = tv_behind_first || (b.spot == 0 && b.what == "TV (id 3)");
  }
  EXPECT_TRUE(tv_behind_first);
}

TEST(SiteConfig, BadSpotsAreNamed) {
  const fs::path base = testing::source_dir() / "assets";
  std::string many;
  for (int i = 0; i < 65; ++i) {
    many += std::string(i > 0 ? ", " : "") + "{ \"floor\": [" + std::to_string(i) +
            ", 0, -2], \"yaw_degrees\": 0 }";
  }
  const auto spots = [](const std::string& list) {
    return R"("remote_avatar": { "avatar": "x.glb", "spots": )" + list + " }";
  };
  const std::pair<std::string, std::string> cases[] = {
      {spots("[]"), "sites/t.json: remote_avatar.spots: expected an array of 1 to 64 spots"},
      {spots("{}"), "sites/t.json: remote_avatar.spots: expected an array of 1 to 64 spots"},
      {spots("[" + many + "]"), "remote_avatar.spots: expected an array of 1 to 64 spots"},
      {spots(R"([{ "floor": [0, 0, "x"], "yaw_degrees": 0 }])"),
       "sites/t.json: remote_avatar.spots[0].floor[2]: not a finite number"},
      {spots(R"([{ "floor": [0, 0, 1], "yaw_degrees": 0 }, { "floor": [0, 0, 1] }])"),
       "sites/t.json: remote_avatar.spots[1]: missing field 'yaw_degrees'"},
      {spots(R"([{ "floor": [0, 0, 1], "yaw_degrees": 0 }, 3])"),
       "sites/t.json: remote_avatar.spots[1]: expected an object"},
      {spots(R"([{ "floor": [0, 0, 1], "yaw_degrees": 0, "avatar": "y.glb" }])"),
       "sites/t.json: remote_avatar.spots[0].avatar: every spot wears remote_avatar.avatar"},
      {spots(
           R"([{ "floor": [0, 0, 1], "yaw_degrees": 0 }, { "floor": [0.1, 0, 1.2], "yaw_degrees": 9 }])"),
       "sites/t.json: remote_avatar.spots[1].floor: less than 0.4 m from spots[0]"},
      {R"("remote_avatar": { "avatar": "x.glb", "floor": [0, 0, 1], "yaw_degrees": 0, "spots": [] })",
       "sites/t.json: remote_avatar: unknown field 'floor'"},
      {R"("remote_avatar": { "floor": [0, 0, 1], "yaw_degrees": 0 })",
       "sites/t.json: remote_avatar: missing field 'avatar'"},
  };
  for (const auto& [replacement, expected] : cases) {
    try {
      parse_site_config(with(kOneSpot, replacement), "sites/t.json", base);
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const deixis::Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

const char kOneStep[] = R"([ { "action": "point", "target": 1 } ])";
const char kTwoSpots[] = R"("remote_avatar": { "avatar": "x.glb", "spots": [
    { "floor": [0, 0, -2], "yaw_degrees": 180 }, { "floor": [1, 0, -1.5], "yaw_degrees": 150 } ] })";

// The test site with two spots and `script`.
std::string with_script(const std::string& script) {
  std::string text = with(kOneStep, script);
  text.replace(text.find(kOneSpot), std::string(kOneSpot).size(), kTwoSpots);
  return text;
}

TEST(SiteConfig, ScriptStepsNamePeopleBySite) {
  const SiteConfig site = parse_site_config(with_script(R"([
      { "action": "look_at", "person": "B", "seconds": 1 },
      { "action": "point", "person": "C" },
      { "action": "point", "target": 1 },
      { "action": "look_at", "person": "B" } ])"),
                                            "sites/t.json", testing::source_dir() / "assets");
  const VirtualUser& user = *site.virtual_user;
  ASSERT_EQ(user.people, (std::vector<std::string>{"B", "C"}));
  ASSERT_EQ(user.script.size(), 4u);
  EXPECT_EQ(user.script[0].target, script_person_target(0));
  EXPECT_EQ(user.script[0].person, "B");
  EXPECT_EQ(user.script[1].target, script_person_target(1));
  EXPECT_EQ(user.script[2].target, 1);
  EXPECT_TRUE(user.script[2].person.empty());
  EXPECT_EQ(user.script[3].target, script_person_target(0));
  EXPECT_TRUE(is_script_person_target(user.script[1].target));
  EXPECT_FALSE(is_script_person_target(kNoTarget));
  EXPECT_EQ(script_person_index(script_person_target(5)), 5u);
}

TEST(SiteConfig, BadPersonStepsAreNamed) {
  const fs::path base = testing::source_dir() / "assets";
  const std::pair<std::string, std::string> cases[] = {
      {R"([{ "action": "touch", "person": "B" }])",
       "sites/t.json: virtual_user.script[0].person: 'touch' takes no person"},
      {R"([{ "action": "rest", "person": "B" }])",
       "sites/t.json: virtual_user.script[0].person: 'rest' takes no person"},
      {R"([{ "action": "point", "person": "B", "target": 1 }])",
       "sites/t.json: virtual_user.script[0].person: give either a target or a person"},
      {R"([{ "action": "point", "person": "T" }])",
       "sites/t.json: virtual_user.script[0].person: 'T' is this site"},
      {R"([{ "action": "point", "person": 3 }])",
       "sites/t.json: virtual_user.script[0].person: expected a string"},
      {R"([{ "action": "point", "person": "" }])",
       "sites/t.json: virtual_user.script[0].person: expected 1 to 64 bytes"},
      {R"([{ "action": "point", "person": "B\u0007" }])",
       "sites/t.json: virtual_user.script[0].person: not valid UTF-8 text"},
      {R"([{ "action": "point", "person": "B" }, { "action": "look_at", "person": "C" },
           { "action": "look_at", "person": "D" }])",
       "sites/t.json: virtual_user.script[2].person: the script names more people than "
       "remote_avatar has spots (2)"},
  };
  for (const auto& [script, expected] : cases) {
    try {
      parse_site_config(with_script(script), "sites/t.json", base);
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const deixis::Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace deixis::site
