#pragma once
// Progress lines of a training run: one per epoch (loss, validation loss, learning rate, time,
// ETA) and, inside long epochs, a line every half minute.

#include <string>
#include <vector>

#include "train/checkpoint.h"

namespace deixis::train {

std::string format_duration(double seconds);  // "1h02m", "4m05s", "12.3s"

// Remaining time at the pace of the last few finished epochs: a long run's pace changes with the
// machine's load and when it is resumed by a faster trainer, and the mean over all epochs would
// lag behind for hours.
double eta_seconds(const std::vector<EpochReport>& history, int epochs_total);

// "epoch 3/80  train 0.04512  val 0.05120  lr 9.51e-05  P 1.00  41.2s  ETA 53m20s"
std::string epoch_line(const EpochReport& report, int epochs_total, double eta);

}  // namespace deixis::train
