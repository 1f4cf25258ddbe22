#pragma once
// The live evaluation's room rules read from a JSON file (`deixis eval --live-rooms N --rules
// FILE`, docs/live-rooms.md "Other rules"), so that rooms can be laid out under other parameters
// than the defaults without a rebuild. Every field is optional (missing: the default of
// RoomRules); the file is untrusted input: bounded in size, every value checked.

#include <filesystem>
#include <string>
#include <string_view>

#include "eval/room_pairs.h"

namespace deixis::eval {

// Reads `file`: {"format": "deixis-room-rules", "version": 1, "point_height": [0.9, 1.2], …}.
// Ranges are [min, max] pairs of metres (spot_distance, point_distance, point_height,
// touch_side, touch_forward, touch_height); between_margin and min_separation are metres,
// point_azimuth_min_deg degrees. Throws deixis::Error naming the file and the field for an
// unknown field, a value that is not a finite number in its bounds, a range whose minimum is
// above its maximum, or a file that is not such JSON.
RoomRules read_room_rules(const std::filesystem::path& file);

// The same from text already read; `file` only names it in errors (the fuzz target's entry).
RoomRules parse_room_rules(std::string_view text, const std::filesystem::path& file);

// The rules as that JSON (every field), for reports.
std::string room_rules_json(const RoomRules& rules);

}  // namespace deixis::eval
