#include "train/adamw.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "core/error.h"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace deixis::train {

namespace {

// Sets flush-to-zero and denormals-are-zero for this thread while in scope (x86's MXCSR; other
// CPUs keep their mode, which is correct, only slower on denormals).
#if defined(__SSE__)
class DenormalsAsZero {
 public:
  DenormalsAsZero() : saved_(_mm_getcsr()) {
    _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero);
  }
  ~DenormalsAsZero() { _mm_setcsr(saved_); }
  DenormalsAsZero(const DenormalsAsZero&) = delete;
  DenormalsAsZero& operator=(const DenormalsAsZero&) = delete;

 private:
  static constexpr unsigned kFlushToZero = 0x8000;       // MXCSR.FZ
  static constexpr unsigned kDenormalsAreZero = 0x0040;  // MXCSR.DAZ
  unsigned saved_;
};
#else
struct DenormalsAsZero {};
#endif

}  // namespace

// UGNet's 2.25 MB of parameters do not fit in L2, so the update runs block by block: each
// block's p, g, m, v stay in L1 across the vectorised Eigen passes.
void adamw_step(const AdamWBuffers& b, const Schedule& s, double lr, std::int64_t step) {
  const std::size_t count = b.values.size();
  if (b.grads.size() != count || b.exp_avg.size() != count || b.exp_avg_sq.size() != count ||
      step < 1) {
    throw Error("adamw_step: buffers of different sizes or a step number below 1");
  }
  const DenormalsAsZero flush;
  using Array = Eigen::Map<Eigen::ArrayXf>;
  const auto t = static_cast<double>(step);
  const auto decay = static_cast<float>(1.0 - lr * s.weight_decay);
  // Each coefficient rounded once from double, as torch passes Python floats to its kernels:
  // 1 − beta2 taken in float (1.0f − 0.999f) would be off by 1.3e-5 relative.
  const auto beta1 = static_cast<float>(s.beta1);
  const auto beta2 = static_cast<float>(s.beta2);
  const auto one_minus_beta1 = static_cast<float>(1.0 - s.beta1);
  const auto one_minus_beta2 = static_cast<float>(1.0 - s.beta2);
  const auto step_size = static_cast<float>(lr / (1.0 - std::pow(s.beta1, t)));
  const auto inverse_correction2_sqrt =
      static_cast<float>(1.0 / std::sqrt(1.0 - std::pow(s.beta2, t)));
  const auto eps = static_cast<float>(s.epsilon);
  constexpr std::size_t kBlock = 1024;
  for (std::size_t first = 0; first < count; first += kBlock) {
    const auto n = static_cast<Eigen::Index>(std::min(kBlock, count - first));
    Array p(b.values.data() + first, n);
    Array g(b.grads.data() + first, n);
    Array m(b.exp_avg.data() + first, n);
    Array v(b.exp_avg_sq.data() + first, n);
    m = m * beta1 + one_minus_beta1 * g;
    v = v * beta2 + one_minus_beta2 * g.square();
    p = p * decay - step_size * m / (v.sqrt() * inverse_correction2_sqrt + eps);
    g.setZero();
  }
}

}  // namespace deixis::train
