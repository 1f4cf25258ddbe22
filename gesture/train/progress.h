#pragma once
// Progress lines of a training run: one per epoch (loss, validation loss, learning rate, time,
// ETA) and, inside long epochs, a line every half minute.

#include <string>

#include "gesture/train/checkpoint.h"

namespace deixis::train {

std::string format_duration(double seconds);  // "1h02m", "4m05s", "12.3s"

// Remaining time from the mean epoch time so far.
double eta_seconds(double mean_epoch_seconds, int epochs_done, int epochs_total);

// "epoch 3/80  train 0.04512  val 0.05120  lr 9.51e-05  P 1.00  41.2s  ETA 53m20s"
std::string epoch_line(const EpochReport& report, int epochs_total, double eta);

}  // namespace deixis::train
