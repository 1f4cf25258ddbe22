// Site configurations: the committed demo sites load; every kind of bad field is named.

#include "site/site_config.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_support.h"

namespace deixis::site {
namespace {

namespace fs = std::filesystem;

TEST(SiteConfig, TheDemoSitesLoad) {
  for (const char* name : {"a.json", "b.json"}) {
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

}  // namespace
}  // namespace deixis::site
