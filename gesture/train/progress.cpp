#include "gesture/train/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace deixis::train {

std::string format_duration(double seconds) {
  char buffer[32];
  if (!std::isfinite(seconds) || seconds < 0) {
    return "?";
  }
  if (seconds < 60) {
    std::snprintf(buffer, sizeof buffer, "%.1fs", seconds);
  } else if (seconds < 3600) {
    const auto s = static_cast<long>(std::lround(seconds));
    std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
  } else {
    const auto m = static_cast<long>(std::lround(seconds / 60));
    std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", m / 60, m % 60);
  }
  return buffer;
}

double eta_seconds(double mean_epoch_seconds, int epochs_done, int epochs_total) {
  return mean_epoch_seconds * std::max(0, epochs_total - epochs_done);
}

std::string epoch_line(const EpochReport& r, int epochs_total, double eta) {
  char validation[32];
  if (std::isfinite(r.validation_loss)) {
    std::snprintf(validation, sizeof validation, "%.5f", r.validation_loss);
  } else {
    std::snprintf(validation, sizeof validation, "-");
  }
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                "epoch %d/%d  train %.5f  val %s  lr %.3e  P %.2f  %s  ETA %s", r.epoch,
                epochs_total, r.train_loss, validation, r.learning_rate, r.teacher_forcing,
                format_duration(r.seconds).c_str(), format_duration(eta).c_str());
  return buffer;
}

}  // namespace deixis::train
