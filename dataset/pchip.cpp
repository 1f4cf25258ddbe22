#include "dataset/pchip.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace deixis::dataset {

namespace {

double sign(double v) {
  return (v > 0) - (v < 0);
}

// SciPy's _edge_case: the three-point estimate, kept monotone.
double edge_slope(double h0, double h1, double m0, double m1) {
  double d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
  if (sign(d) != sign(m0)) {
    d = 0;
  } else if (sign(m0) != sign(m1) && std::abs(d) > std::abs(3 * m0)) {
    d = 3 * m0;
  }
  return d;
}

}  // namespace

Pchip::Pchip(std::span<const double> x, std::span<const double> y)
    : x_(x.begin(), x.end()), y_(y.begin(), y.end()), slope_(x.size(), 0.0) {
  const std::size_t n = x_.size();
  if (n == 0 || y_.size() != n) {
    throw Error("pchip: need as many values as knots, at least one");
  }
  for (std::size_t k = 1; k < n; ++k) {
    if (!(x_[k] > x_[k - 1])) {
      throw Error("pchip: knots must increase strictly (knot " + std::to_string(k) + ")");
    }
  }
  if (n == 1) {
    return;
  }
  std::vector<double> h(n - 1);
  std::vector<double> m(n - 1);
  for (std::size_t k = 0; k + 1 < n; ++k) {
    h[k] = x_[k + 1] - x_[k];
    m[k] = (y_[k + 1] - y_[k]) / h[k];
  }
  if (n == 2) {
    slope_[0] = slope_[1] = m[0];
    return;
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    if (m[k - 1] * m[k] <= 0) {
      slope_[k] = 0;  // a local extremum or a flat piece: no overshoot
    } else {
      const double w1 = 2 * h[k] + h[k - 1];
      const double w2 = h[k] + 2 * h[k - 1];
      slope_[k] = (w1 + w2) / (w1 / m[k - 1] + w2 / m[k]);
    }
  }
  slope_[0] = edge_slope(h[0], h[1], m[0], m[1]);
  slope_[n - 1] = edge_slope(h[n - 2], h[n - 3], m[n - 2], m[n - 3]);
}

double Pchip::operator()(double x) const {
  const std::size_t n = x_.size();
  if (n == 1) {
    return y_[0];
  }
  // The interval [x_k, x_k+1] holding x (clamped to the ends: no extrapolation).
  x = std::clamp(x, x_.front(), x_.back());
  const auto it = std::upper_bound(x_.begin(), x_.end(), x);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - x_.begin()), n - 1) - 1;
  const double h = x_[k + 1] - x_[k];
  const double t = (x - x_[k]) / h;
  const double t2 = t * t;
  const double t3 = t2 * t;
  return (2 * t3 - 3 * t2 + 1) * y_[k] + (t3 - 2 * t2 + t) * h * slope_[k] +
         (-2 * t3 + 3 * t2) * y_[k + 1] + (t3 - t2) * h * slope_[k + 1];
}

std::vector<double> pchip_resample(std::span<const double> y, std::size_t count) {
  std::vector<double> x(y.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    x[k] = static_cast<double>(k);
  }
  const Pchip f(x, y);
  std::vector<double> out(count);
  const double last = static_cast<double>(y.size() - 1);
  for (std::size_t j = 0; j < count; ++j) {
    const double at = count == 1 ? 0.0 : static_cast<double>(j) / static_cast<double>(count - 1);
    out[j] = f(last * at);
  }
  return out;
}

}  // namespace deixis::dataset
