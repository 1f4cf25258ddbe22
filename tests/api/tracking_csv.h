#pragma once
// The examples' recorded tracking (examples/data/pointing.csv, the column layout of `deixis
// capture csv`) read for the tests, as the C API's frames and as the runtime's own, and the
// in-tree translator the examples' output is compared with: presence::RemoteAvatar configured
// as examples/c/play_tracking.c configures its translator through the C API.
#include <filesystem>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "deixis/deixis.h"

namespace deixis::testing {

std::filesystem::path examples_dir();

// Every row of the CSV as a C API frame. Throws std::runtime_error on a missing column.
std::vector<deixis_tracking_frame> read_tracking_csv(const std::filesystem::path& csv);

// The runtime's frame for a C frame: quaternions normalised, as the C API does.
TrackingFrame runtime_frame(const deixis_tracking_frame& c);

// One line per tick, "tick visible held x y z" (the avatar's deictic fingertip after IK), as
// the examples print it: the in-tree translator's answer on the same input.
std::vector<std::string> in_tree_fingertips(const std::filesystem::path& csv,
                                            const std::filesystem::path& target_map);

// Parses "tick visible held x y z" lines; the fingertips as numbers (tick order).
struct PrintedTick {
  long tick = 0;
  int visible = 0;
  int held = 0;
  Vec3 fingertip = Vec3::Zero();
};
std::vector<PrintedTick> parse_ticks(const std::vector<std::string>& lines);

}  // namespace deixis::testing
