#pragma once
// Fig. 5 of the paper as a PNG: four panels (MPJPE, MPJRE, MPJLVE, MPJAVE) against the duration
// of missed tracking, one line per row evaluated, drawn with dataset/raster.h.

#include <filesystem>
#include <span>

#include "eval/tables.h"

namespace deixis::eval {

// Throws deixis::Error naming the path if it cannot be written.
void write_figure5(std::span<const Figure5Series> series, const std::filesystem::path& path);

}  // namespace deixis::eval
