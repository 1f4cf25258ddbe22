#include "train/group_norm.h"

#include <cmath>

namespace deixis::train {

void group_norm(const Eigen::Ref<const RowMatrix>& x, Eigen::Index groups, float eps,
                const ConstVectorMap& gamma, const ConstVectorMap& beta,
                Eigen::Ref<RowMatrix> x_hat, float* rstd, Eigen::Ref<RowMatrix> y) {
  const Eigen::Index size = x.cols() / groups;
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    for (Eigen::Index g = 0; g < groups; ++g) {
      const auto in = x.row(r).segment(g * size, size);
      auto centred = x_hat.row(r).segment(g * size, size);
      centred = in.array() - in.mean();
      const float inverse =
          1.0f / std::sqrt(centred.squaredNorm() / static_cast<float>(size) + eps);
      rstd[r * groups + g] = inverse;
      centred *= inverse;
    }
  }
  y = (x_hat.array().rowwise() * gamma.array()).rowwise() + beta.array();
}

void group_norm_backward(const Eigen::Ref<const RowMatrix>& dy,
                         const Eigen::Ref<const RowMatrix>& x_hat, const float* rstd,
                         Eigen::Index groups, const ConstVectorMap& gamma, VectorMap d_gamma,
                         VectorMap d_beta, Eigen::Ref<RowMatrix> dx) {
  d_gamma = (dy.array() * x_hat.array()).colwise().sum();
  d_beta = dy.colwise().sum();
  dx = (dy.array().rowwise() * gamma.array()).matrix();  // g, made ∂L/∂x in place below
  const Eigen::Index size = dy.cols() / groups;
  const auto n = static_cast<float>(size);
  for (Eigen::Index r = 0; r < dy.rows(); ++r) {
    for (Eigen::Index k = 0; k < groups; ++k) {
      auto g = dx.row(r).segment(k * size, size);
      const auto xh = x_hat.row(r).segment(k * size, size);
      const float mean_g = g.sum() / n;
      const float mean_gx = g.dot(xh) / n;
      g = rstd[r * groups + k] * (g.array() - mean_g - xh.array() * mean_gx);
    }
  }
}

}  // namespace deixis::train
