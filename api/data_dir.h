#pragma once
// Where the shipped weights and default avatar are (deixis_data_dir in include/deixis/deixis.h).
#include <filesystem>

namespace deixis::api {

// Throws deixis::Error when no data directory exists.
std::filesystem::path data_dir();

}  // namespace deixis::api
