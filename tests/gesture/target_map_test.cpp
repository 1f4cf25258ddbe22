// Target maps: round trip, the demo rooms, and every kind of bad field named with its path.

#include "core/target_map.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "test_support.h"

namespace deixis {
namespace {

TEST(TargetMap, RoundTripsThroughJson) {
  TargetMap map;
  map.site = "A";
  map.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(1, 2, -3), Vec3(0.4f, 0.4f, 0.4f)});
  map.objects.push_back(
      {7, "TV", TargetKind::kScreen, Vec3(-1, 1.3f, -2), Vec3(1.2f, 0.7f, 0.05f)});
  const TargetMap back = parse_target_map(to_json(map), "memory");
  ASSERT_EQ(back.objects.size(), 2u);
  EXPECT_EQ(back.site, "A");
  EXPECT_EQ(back.objects[1].name, "TV");
  EXPECT_EQ(back.objects[1].kind, TargetKind::kScreen);
  EXPECT_TRUE(back.objects[0].position.isApprox(Vec3(1, 2, -3)));
  EXPECT_EQ(back.find(7), &back.objects[1]);
  EXPECT_EQ(back.find(3), nullptr);
}

TEST(TargetMap, TheDemoRoomsShareTheirIds) {
  const TargetMap a = read_target_map(testing::source_dir() / "assets/rooms/a.json");
  const TargetMap b = read_target_map(testing::source_dir() / "assets/rooms/b.json");
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (const TargetObject& o : a.objects) {
    const TargetObject* copy = b.find(o.id);
    ASSERT_NE(copy, nullptr) << o.name;
    EXPECT_EQ(copy->name, o.name);
    EXPECT_GT((copy->position - o.position).norm(), 0.3f) << o.name << " stands elsewhere in B";
  }
}

TEST(TargetMap, BadFieldsAreNamedWithTheirPath) {
  const std::string good =
      R"({"format": "deixis-target-map", "version": 1, "site": "B", "objects": [
    {"id": 1, "name": "A", "kind": "sphere", "position": [0, 1, -2], "size": [0.2, 0.2, 0.2]},
    {"id": 2, "name": "B", "kind": "box", "position": [1, 1, -2], "size": [0.2, 0.2, 0.2]}]})";
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::pair<std::string, std::string> cases[] = {
      {with("[1, 1, -2]", "[1, \"high\", -2]"),
       "rooms/b.json: objects[1].position[1]: not a finite number"},
      {with("[1, 1, -2]", "[1, 1e400, -2]"), "rooms/b.json: not valid JSON"},
      {with("\"box\"", "\"cube\""), "objects[1].kind: unknown kind 'cube'"},
      {with("\"id\": 2", "\"id\": 1"), "objects[1].id: id 1 is used twice"},
      {with("\"id\": 2", "\"id\": 0"), "objects[1].id: expected an integer from 1 to 1000000"},
      {with("[0.2, 0.2, 0.2]}]", "[0.2, -1, 0.2]}]"),
       "objects[1].size[1]: expected a size in (0, 100] m"},
      {with("\"version\": 1", "\"version\": 9"), "version: this Deixis reads version 1"},
      {with("\"format\": \"deixis-target-map\"", "\"format\": \"x\""),
       "format: expected \"deixis-target-map\""},
      {with("\"name\": \"A\", ", ""), "objects[0]: missing field 'name'"},
      {with("\"name\": \"A\"", "\"name\": \"A\", \"mass\": 3"), "objects[0]: unknown field 'mass'"},
      {"[1, 2]", "rooms/b.json: expected a JSON object"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_target_map(text, "rooms/b.json");
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(read_target_map("/nonexistent/room.json"), Error);
}

// A target map is a file from anywhere; each hostile class is a clear error.
TEST(TargetMap, HostileFilesAreRefusedNamingFileAndPlace) {
  const std::string good =
      R"({"format": "deixis-target-map", "version": 1, "site": "B", "objects": [
    {"id": 1, "name": "A", "kind": "sphere", "position": [0, 1, -2], "size": [0.2, 0.2, 0.2]}]})";
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::string deep = std::string(100, '[') + std::string(100, ']');
  const std::pair<std::string, std::string> cases[] = {
      {with("\"site\": \"B\"", "\"site\": \"B\", \"x\": " + deep),
       "rooms/b.json: nested deeper than 64 levels"},
      {with("\"name\": \"A\"", "\"name\": \"A\", \"name\": \"Z\""),
       "rooms/b.json: duplicate key 'name' in objects[0]"},
      {with("\"site\": \"B\"", "\"site\": \"B\", \"site\": \"C\""),
       "rooms/b.json: duplicate key 'site' in the top-level object"},
      // 2^64 − 1: as int64 it is −1; 2^32 + 1 as int is 1, the version this Deixis reads.
      {with("\"id\": 1", "\"id\": 18446744073709551615"),
       "rooms/b.json: objects[0].id: expected an integer from 1 to 1000000"},
      {with("\"version\": 1", "\"version\": 4294967297"),
       "rooms/b.json: version: expected an integer from 0 to 1000"},
      {with("\"name\": \"A\"", "\"name\": \"A\\u0007\""),
       "rooms/b.json: objects[0].name: not valid UTF-8 text without control characters"},
      {with("\"name\": \"A\"", "\"name\": \"" + std::string(65, 'x') + "\""),
       "rooms/b.json: objects[0].name: expected 1 to 64 bytes, found 65"},
      {with("\"name\": \"A\"", "\"name\": \"\xc3\""), "rooms/b.json: not valid JSON"},
      {with("\"site\": \"B\"", "\"site\": \"B\\nB\""),
       "rooms/b.json: site: not valid UTF-8 text without control characters"},
      {with("\"site\": \"B\"", "\"site\": \"" + std::string(70, 's') + "\""),
       "rooms/b.json: site: expected 0 to 64 bytes, found 70"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parse_target_map(text, "rooms/b.json");
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // An empty site is allowed, as on the wire.
  EXPECT_EQ(parse_target_map(with("\"site\": \"B\"", "\"site\": \"\""), "m").site, "");
  // A device is not a file: read with a bound, never to the end.
  EXPECT_THROW(read_target_map("/dev/zero"), Error);
}

TEST(TargetMap, ClosestSurfacePoint) {
  const TargetObject sphere{1, "S", TargetKind::kSphere, Vec3(0, 1, 0), Vec3(0.4f, 0.4f, 0.4f)};
  EXPECT_TRUE(closest_surface_point(sphere, Vec3(0, 1, 2)).isApprox(Vec3(0, 1, 0.2f), 1e-6f));
  const TargetObject box{2, "B", TargetKind::kBox, Vec3(0, 1, 0), Vec3(0.2f, 0.4f, 0.6f)};
  EXPECT_TRUE(
      closest_surface_point(box, Vec3(0.05f, 1.1f, 2)).isApprox(Vec3(0.05f, 1.1f, 0.3f), 1e-6f));
  // From inside, the nearest face (x: 0.1 − 0.08 = 0.02 away).
  EXPECT_TRUE(closest_surface_point(box, Vec3(0.08f, 1, 0)).isApprox(Vec3(0.1f, 1, 0), 1e-6f));
}

}  // namespace
}  // namespace deixis
