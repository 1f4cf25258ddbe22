#pragma once
// Monotone piecewise cubic Hermite interpolation (Fritsch & Carlson 1980), as SciPy's
// PchipInterpolator computes it (the authors' speed augmentation,
// docs/conventions.md#training-data): slopes are the weighted harmonic mean of neighbouring
// secants, zero at local extrema, and the one-sided three-point formula at the ends. It never
// overshoots the data and preserves monotonicity, so labels stay in [0, 1] and ramps stay monotone.

#include <span>
#include <vector>

namespace deixis::dataset {

class Pchip {
 public:
  // Knots x (strictly increasing) and values y, same length ≥ 1.
  Pchip(std::span<const double> x, std::span<const double> y);
  double operator()(double x) const;

 private:
  std::vector<double> x_;
  std::vector<double> y_;
  std::vector<double> slope_;
};

// Resamples values given at uniformly spaced knots to `count` uniformly spaced samples over the
// same span (the authors' np.linspace(0, 1, n) → np.linspace(0, 1, m)).
std::vector<double> pchip_resample(std::span<const double> y, std::size_t count);

}  // namespace deixis::dataset
