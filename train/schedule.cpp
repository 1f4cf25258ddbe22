#include "train/schedule.h"

#include <algorithm>
#include <cmath>

#include <string>

#include "core/error.h"
#include "train/network_kind.h"

namespace deixis::train {

double Schedule::learning_rate_at(int epoch) const {
  return learning_rate * std::pow(learning_rate_decay, std::max(0, epoch - 1));
}

double Schedule::teacher_forcing_at(int epoch) const {
  if (!scheduled_sampling || epoch <= teacher_forcing_epochs) {
    return 1.0;
  }
  if (epoch <= autoregressive_from_epoch) {
    // train_UGNet.py: P = 1 − (epoch − c1) / (c2 − c1) for c1 < epoch ≤ c2.
    return 1.0 - static_cast<double>(epoch - teacher_forcing_epochs) /
                     static_cast<double>(autoregressive_from_epoch - teacher_forcing_epochs);
  }
  return 0.0;
}

Schedule compressed(const Schedule& full, int epochs) {
  if (epochs < 2 || epochs > full.epochs) {
    throw Error("a schedule of " + std::to_string(full.epochs) +
                " epochs can be compressed to 2 to " + std::to_string(full.epochs) +
                " epochs, not " + std::to_string(epochs));
  }
  Schedule s = full;
  s.epochs = epochs;
  s.learning_rate_decay = std::pow(full.learning_rate_decay, static_cast<double>(full.epochs - 1) /
                                                                 static_cast<double>(epochs - 1));
  const double scale = static_cast<double>(epochs) / static_cast<double>(full.epochs);
  s.teacher_forcing_epochs = static_cast<int>(std::lround(full.teacher_forcing_epochs * scale));
  s.autoregressive_from_epoch =
      std::max(s.teacher_forcing_epochs + 1,
               static_cast<int>(std::lround(full.autoregressive_from_epoch * scale)));
  return s;
}

Schedule continued(const Schedule& full, int epochs) {
  if (epochs < 1) {
    throw Error("a schedule can be continued by 1 or more epochs, not " + std::to_string(epochs));
  }
  Schedule s = full;
  s.epochs = epochs;
  s.learning_rate = full.learning_rate_at(full.epochs + 1);
  if (full.scheduled_sampling) {
    // P as after full's last epoch, for every epoch: 1 (all teacher forcing) or 0 (all
    // autoregressive). A schedule cut short inside its ramp has no single P to keep.
    const double p = full.teacher_forcing_at(full.epochs + 1);
    if (p > 0.0 && p < 1.0) {
      throw Error("a schedule that ends inside its scheduled-sampling ramp cannot be continued");
    }
    s.teacher_forcing_epochs = p == 1.0 ? epochs : 0;
    s.autoregressive_from_epoch = p == 1.0 ? epochs + 1 : 0;
  }
  return s;
}

Schedule default_schedule(Family family) {
  Schedule s;
  switch (family) {
    case Family::kMpnet:
      break;  // the defaults above
    case Family::kUgnet:
      s.epochs = 120;
      s.batch_size = 32;
      s.learning_rate_decay = 0.99;
      s.scheduled_sampling = true;
      break;
    case Family::kMotionAutoencoder:
      s.epochs = 600;
      s.batch_size = 8;
      s.learning_rate = 1e-3;
      s.learning_rate_decay = 0.999;
      s.weight_decay = 0.0;
      break;
  }
  return s;
}

}  // namespace deixis::train
