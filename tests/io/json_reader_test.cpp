// Untrusted JSON: the reader every Deixis JSON format goes through bounds the nesting
// depth before parsing, refuses duplicate keys naming the key and where it is, checks integers
// whatever their sign (no wrap above INT64_MAX), and holds names to the wire's text rules.

#include "core/io/json_reader.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/io/json_guard.h"
#include "core/io/text_rules.h"
#include "error_of.h"
#include "net/protocol.h"
#include "test_support.h"

namespace deixis {
namespace {

// The wire's limit and the file readers' limit are one number.
static_assert(kMaxNameBytes == net::kMaxTextBytes);

using deixis::testing::error_of;

std::string nested(std::size_t depth) {
  return std::string(depth, '[') + std::string(depth, ']');
}

TEST(JsonReader, DepthIsBoundedBeforeParsing) {
  const JsonReader r("f.json");
  EXPECT_NO_THROW(r.parse_object("{\"a\": " + nested(63) + "}"));  // 64 levels with the object
  EXPECT_EQ(error_of([&] { r.parse_object("{\"a\": " + nested(64) + "}"); }),
            "f.json: nested deeper than 64 levels of arrays and objects (at byte 69)");
  // A million levels: refused by counting, never by a recursion that runs out of stack.
  const std::string deep = std::string(1'000'000, '{');
  EXPECT_NE(error_of([&] { r.parse_object(deep); }).find("nested deeper than 64"),
            std::string::npos);
  // Brackets in strings are text.
  EXPECT_NO_THROW(r.parse_object("{\"a\": \"" + nested(100) + "\\\"[[\"}"));
}

TEST(JsonReader, DuplicateKeysAreNamedWithTheirPlace) {
  const JsonReader r("rooms/a.json");
  EXPECT_EQ(error_of([&] { r.parse_object(R"({"site": "A", "site": "B"})"); }),
            "rooms/a.json: duplicate key 'site' in the top-level object");
  EXPECT_EQ(error_of([&] {
              r.parse_object(R"({"objects": [{"id": 1}, {"id": 2, "name": "x", "id": 3}]})");
            }),
            "rooms/a.json: duplicate key 'id' in objects[1]");
  EXPECT_EQ(error_of([&] { r.parse_object(R"({"a": {"b": [[1, {"k": 1, "k": 2}]]}})"); }),
            "rooms/a.json: duplicate key 'k' in a.b[0][1]");
  // The same key in different objects is fine.
  EXPECT_NO_THROW(r.parse_object(R"({"a": {"k": 1}, "b": {"k": 2}, "c": [{"k": 1}, {"k": 2}]})"));
}

TEST(JsonReader, IntegersAboveInt64MaxDoNotWrap) {
  const JsonReader r("f.json");
  const auto j = r.parse_object(R"({"big": 18446744073709551615, "wrap": 9223372036854775809,
                                    "neg": -5, "ok": 7, "float": 7.5})");
  // 2^64 − 1 read as int64 is −1, and 2^63 + 1 is −2^63 + 1: both would pass a check below zero.
  EXPECT_EQ(error_of([&] { r.integer_in(j["big"], "big", -10, 10); }),
            "f.json: big: expected an integer from -10 to 10, found 18446744073709551615");
  EXPECT_NE(error_of([&] {
              r.integer_in(j["wrap"], "wrap", std::numeric_limits<std::int64_t>::min(), 0);
            }).find("wrap: expected an integer"),
            std::string::npos);
  EXPECT_EQ(r.integer_in(j["neg"], "neg", -10, 10), -5);
  EXPECT_EQ(r.integer_in(j["ok"], "ok", 1, 10), 7);
  EXPECT_NE(error_of([&] { r.integer_in(j["ok"], "ok", 8, 10); }).find("found 7"),
            std::string::npos);
  EXPECT_NE(error_of([&] { r.integer_in(j["float"], "float", 0, 10); }).find("found 7.5"),
            std::string::npos);
}

TEST(JsonReader, NamesFollowTheWiresRules) {
  const JsonReader r("f.json");
  const auto j = r.parse_object(
      R"({"ok": "Jüpiter — 東京", "tab": "a\tb", "nul": "a\u0000b", "c1": "a\u0085b",
          "long": "0123456789012345678901234567890123456789012345678901234567890123x",
          "max": "0123456789012345678901234567890123456789012345678901234567890123",
          "empty": ""})");
  EXPECT_EQ(r.name(j["ok"], "ok"), "Jüpiter — 東京");
  EXPECT_EQ(r.name(j["max"], "max").size(), 64u);
  EXPECT_EQ(error_of([&] { r.name(j["tab"], "tab"); }),
            "f.json: tab: not valid UTF-8 text without control characters");
  EXPECT_NE(error_of([&] { r.name(j["nul"], "nul"); }).find("nul: not valid UTF-8"),
            std::string::npos);
  EXPECT_NE(error_of([&] { r.name(j["c1"], "c1"); }).find("c1: not valid UTF-8"),
            std::string::npos);
  EXPECT_EQ(error_of([&] { r.name(j["long"], "long"); }),
            "f.json: long: expected 1 to 64 bytes, found 65");
  EXPECT_NE(error_of([&] { r.name(j["empty"], "empty"); }).find("expected 1 to 64 bytes"),
            std::string::npos);
  EXPECT_EQ(r.name(j["empty"], "empty", 0), "");
  // Invalid UTF-8 in the file itself (nlohmann refuses it while parsing).
  EXPECT_NE(error_of([&] { r.parse_object("{\"n\": \"\xc0\xaf\"}"); }).find("not valid JSON"),
            std::string::npos);
}

TEST(JsonReader, FilesAreReadWithABound) {
  EXPECT_NE(
      error_of([] { JsonReader::read_file("/dev/zero"); }).find("/dev/zero: more than the 16 MiB"),
      std::string::npos);
  EXPECT_EQ(error_of([] { JsonReader::read_file("/nonexistent/x.json"); }),
            "/nonexistent/x.json: cannot open");
  EXPECT_EQ(error_of([] {
              JsonReader("big.json").parse_object(std::string(kMaxJsonFileBytes + 1, ' '));
            }),
            "big.json: 16777217 bytes is more than the 16 MiB a JSON file may have");
}

TEST(TextRules, SameAsTheWire) {
  EXPECT_TRUE(is_wire_text(std::string_view("Jupiter")));
  EXPECT_FALSE(is_wire_text(std::string_view("\xed\xa0\x80")));      // a surrogate
  EXPECT_FALSE(is_wire_text(std::string_view("\xf4\x90\x80\x80")));  // beyond U+10FFFF
  EXPECT_FALSE(is_wire_text(std::string_view("\xe6\x9d")));          // cut short
}

}  // namespace
}  // namespace deixis
