#include "gesture/nn/activations.h"

namespace deixis::nn {

void elu_inplace(float* x, std::size_t count) noexcept {
  for (std::size_t i = 0; i < count; ++i) {
    x[i] = elu(x[i]);
  }
}

}  // namespace deixis::nn
