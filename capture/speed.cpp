#include "capture/speed.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.h"
#include "dataset/pchip.h"

namespace deixis::capture {

namespace {

// Rotation from nearly orthonormal columns, keeping the third (forward) column's direction.
Mat3 orthonormalise(const Mat3& R) {
  const Vec3 z = R.col(2).normalized();
  const Vec3 x = R.col(1).cross(z).normalized();
  Mat3 out;
  out.col(0) = x;
  out.col(1) = z.cross(x);
  out.col(2) = z;
  return out;
}

// Resamples one scalar channel read from and written to the frames by accessors.
template <class In, class Read, class Write>
void resample_channel(const std::vector<In>& in, std::size_t count, Read read, Write write) {
  std::vector<double> y(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    y[i] = read(in[i]);
  }
  const std::vector<double> out = dataset::pchip_resample(y, count);
  for (std::size_t j = 0; j < count; ++j) {
    write(j, out[j]);
  }
}

}  // namespace

Sequence resample_speed(const Sequence& in, float speed) {
  if (!(speed > 0.0f) || !std::isfinite(speed)) {
    throw Error("resample_speed: speed must be a positive number, got " + std::to_string(speed));
  }
  const std::size_t n = in.size();
  if (n < 2) {
    throw Error("resample_speed: a sequence needs at least 2 frames");
  }
  const auto count = std::max<std::size_t>(
      2, static_cast<std::size_t>(std::floor(static_cast<double>(n) / static_cast<double>(speed))));
  Sequence out = in;
  out.speed = in.speed * speed;
  out.joints.clear();
  out.frames.assign(count, TrackingFrame{});
  out.labels.assign(count, Labels{});
  out.phase_keys.assign(count, 0);

  // Fingertips in their wrist frames (constant for a rigid hand, up to rounding).
  std::vector<std::array<Vec3, 2>> tip_local(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int h = 0; h < 2; ++h) {
      tip_local[i][h] =
          transform_point(inverse(in.frames[i].T_world_wrist[h]), in.frames[i].index_tip[h]);
    }
  }

  using F = TrackingFrame;
  auto channel = [&](std::function<float(const F&)> read, std::function<float&(F&)> field) {
    resample_channel(
        in.frames, count, [&](const F& f) { return static_cast<double>(read(f)); },
        [&](std::size_t j, double v) { field(out.frames[j]) = static_cast<float>(v); });
  };
  for (int a = 0; a < 3; ++a) {
    channel([a](const F& f) { return f.T_world_head.translation[a]; },
            [a](F& f) -> float& { return f.T_world_head.translation[a]; });
    channel([a](const F& f) { return f.gaze[a]; }, [a](F& f) -> float& { return f.gaze[a]; });
    for (int h = 0; h < 2; ++h) {
      channel([a, h](const F& f) { return f.T_world_wrist[h].translation[a]; },
              [a, h](F& f) -> float& { return f.T_world_wrist[h].translation[a]; });
    }
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      channel([r, c](const F& f) { return f.T_world_head.rotation(r, c); },
              [r, c](F& f) -> float& { return f.T_world_head.rotation(r, c); });
      for (int h = 0; h < 2; ++h) {
        channel([r, c, h](const F& f) { return f.T_world_wrist[h].rotation(r, c); },
                [r, c, h](F& f) -> float& { return f.T_world_wrist[h].rotation(r, c); });
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    resample_channel(
        in.labels, count, [k](const Labels& l) { return static_cast<double>(l[k]); },
        [&](std::size_t j, double v) {
          out.labels[j][k] = std::clamp(static_cast<float>(v), 0.0f, 1.0f);
        });
  }

  const double stretch = static_cast<double>(n - 1) / static_cast<double>(count - 1);
  for (std::size_t j = 0; j < count; ++j) {
    F& f = out.frames[j];
    const auto nearest =
        std::min(n - 1, static_cast<std::size_t>(std::lround(static_cast<double>(j) * stretch)));
    const F& source = in.frames[nearest];
    f.time = static_cast<double>(j) / kFrameRate;
    f.valid = source.valid;
    f.head_target = source.head_target;
    f.hand_target = source.hand_target;
    f.head_target_position = source.head_target_position;
    f.hand_target_position = source.hand_target_position;
    f.gaze.normalize();
    f.T_world_head.rotation = orthonormalise(f.T_world_head.rotation);
    for (int h = 0; h < 2; ++h) {
      f.T_world_wrist[h].rotation = orthonormalise(f.T_world_wrist[h].rotation);
      f.index_tip[h] = transform_point(f.T_world_wrist[h], tip_local[nearest][h]);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (in.phase_keys[i]) {
      const auto j = static_cast<std::size_t>(std::lround(static_cast<double>(i) / stretch));
      out.phase_keys[std::min(j, count - 1)] = 1;
    }
  }
  return out;
}

}  // namespace deixis::capture
