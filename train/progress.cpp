#include "train/progress.h"

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

double eta_seconds(const std::vector<EpochReport>& history, int epochs_total) {
  constexpr std::size_t kRecentEpochs = 5;
  const std::size_t recent = std::min(kRecentEpochs, history.size());
  if (recent == 0) {
    return 0;
  }
  double sum = 0;
  for (std::size_t i = history.size() - recent; i < history.size(); ++i) {
    sum += history[i].seconds;
  }
  const int remaining = std::max(0, epochs_total - static_cast<int>(history.size()));
  return sum / static_cast<double>(recent) * remaining;
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
