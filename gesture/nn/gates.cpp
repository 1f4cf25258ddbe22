#include "gesture/nn/gates.h"

#include <algorithm>

#include "gesture/nn/simd_target.h"

#if DEIXIS_AVX512_KERNEL
#include <immintrin.h>
#endif

namespace deixis::nn {
namespace {

using GatePacket = Eigen::internal::packet_traits<float>::type;

// values[0, padded) ← op(values), packet by packet through the functor's packetOp only (Eigen's
// scalar_logistic_op, scalar_tanh_op); `padded` is a whole number of packets.
template <typename Op>
void apply_in_packets(float* values, std::size_t padded, Op op) noexcept {
  // GCC warns that a vector type's attributes are dropped as a template argument; Eigen's own
  // headers silence the same warning for their uses of it.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"
  for (std::size_t i = 0; i < padded; i += kGatePacketFloats) {
    Eigen::internal::pstoreu(values + i,
                             op.packetOp(Eigen::internal::ploadu<GatePacket>(values + i)));
  }
#pragma GCC diagnostic pop
}

void eigen_logistic(float* values, std::size_t padded) noexcept {
  apply_in_packets(values, padded, Eigen::internal::scalar_logistic_op<float>{});
}

void eigen_tanh(float* values, std::size_t padded) noexcept {
  apply_in_packets(values, padded, Eigen::internal::scalar_tanh_op<float>{});
}

// The build's GRU step in lanes in two passes, as gru_gates_avx512 below: Eigen's own packet
// logistic and tanh (the same functors as eigen_logistic and eigen_tanh), its packet add and
// multiply-add (fused where the build has FMA, as lanewise::multiply_add is), so the same bits as
// the five passes over the buffers it replaces (the sums, the logistic, n's argument, the tanh,
// h): 0.2 µs a person less at 64 on the Xeon held to its AVX2 kernels (decision 95).
// `values` is a multiple of kGatePacketFloats.
void gru_gates_in_packets(const float* gi, float* gh, float* h, std::size_t values) noexcept {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wignored-attributes"
  using Eigen::internal::padd;
  using Eigen::internal::ploadu;
  using Eigen::internal::pmadd;
  using Eigen::internal::pstoreu;
  using Eigen::internal::psub;
  const Eigen::internal::scalar_logistic_op<float> logistic;
  const Eigen::internal::scalar_tanh_op<float> tanh;
  const std::size_t rz_size = 2 * values;
  for (std::size_t i = 0; i < rz_size; i += kGatePacketFloats) {
    pstoreu(gh + i,
            logistic.packetOp(padd(ploadu<GatePacket>(gi + i), ploadu<GatePacket>(gh + i))));
  }
  const float* reset = gh;
  const float* update = gh + values;
  const float* gh_candidate = gh + rz_size;
  const float* gi_candidate = gi + rz_size;
  for (std::size_t k = 0; k < values; k += kGatePacketFloats) {
    const GatePacket n =
        tanh.packetOp(pmadd(ploadu<GatePacket>(reset + k), ploadu<GatePacket>(gh_candidate + k),
                            ploadu<GatePacket>(gi_candidate + k)));
    const GatePacket h_old = ploadu<GatePacket>(h + k);
    pstoreu(h + k, pmadd(ploadu<GatePacket>(update + k), psub(h_old, n), n));
  }
#pragma GCC diagnostic pop
}

#if DEIXIS_AVX512_KERNEL
// GCC 12's headers implement _mm512_min_ps and _mm512_max_ps through _mm512_undefined_ps(), a
// self-initialised variable its flow analysis then reports as maybe uninitialised once inlined.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

// Eigen 3.4's float logistic (UnaryFunctors.h, scalar_logistic_op<float>::packetOp) and tanh
// (MathFunctionsImpl.h, generic_fast_tanh_float) as they compile with EIGEN_VECTORIZE_FMA, whose
// constants they are, in 16-float vectors. Operand orders follow Eigen's AVX packets: its pmin(a,
// b) and pmax(a, b) are vminps/vmaxps with the operands swapped (b, a), which decides what a NaN
// gives; pcmp_lt is an ordered, quiet less-than; pselect(m, a, b) takes a where m is set.

// c[0]·x^(N−1) + … + c[N−1] by Horner's rule as Eigen writes it: pmadd(x, c[0], c[1]), then
// pmadd(x, p, c[k]) down to the constant term.
template <std::size_t N>
DEIXIS_AVX512_TARGET inline __m512 horner(__m512 x, const float (&c)[N]) noexcept {
  __m512 p = _mm512_fmadd_ps(x, _mm512_set1_ps(c[0]), _mm512_set1_ps(c[1]));
  for (std::size_t k = 2; k < N; ++k) {
    p = _mm512_fmadd_ps(x, p, _mm512_set1_ps(c[k]));
  }
  return p;
}

// The logistic where no value is below −9 (there Eigen takes e^x instead; the caller checks):
// 1/2 + p(x)/q(x), p odd, q even.
DEIXIS_AVX512_TARGET inline __m512 logistic16(__m512 x_in) noexcept {
  static constexpr float kP[] = {4.37031012579801e-11f, 1.15627324459942e-07f,
                                 6.08574864600143e-05f, 8.51377133304701e-03f,
                                 2.48287947061529e-01f};
  static constexpr float kQ[] = {6.10247389755681e-13f, 5.76102136993427e-09f,
                                 6.29106785017040e-06f, 1.70198817374094e-03f,
                                 1.16817656904453e-01f, 9.93151921023180e-01f};
  const __m512 x = _mm512_min_ps(_mm512_set1_ps(15.7243833541870117f), x_in);
  const __m512 x2 = _mm512_mul_ps(x, x);
  const __m512 p = _mm512_mul_ps(x, horner(x2, kP));
  const __m512 q = horner(x2, kQ);
  return _mm512_add_ps(_mm512_div_ps(p, q), _mm512_set1_ps(0.5f));
}

// tanh: x itself below 0.0004 in magnitude, else p(x)/q(x) on x clamped to ±7.9988.
DEIXIS_AVX512_TARGET inline __m512 tanh16(__m512 x_in) noexcept {
  static constexpr float kP[] = {
      -2.76076847742355e-16f, 2.00018790482477e-13f, -8.60467152213735e-11f, 5.12229709037114e-08f,
      1.48572235717979e-05f,  6.37261928875436e-04f, 4.89352455891786e-03f};
  static constexpr float kQ[] = {1.19825839466702e-06f, 1.18534705686654e-04f,
                                 2.26843463243900e-03f, 4.89352518554385e-03f};
  constexpr float kClamp = 7.99881172180175781f;
  const __m512 x =
      _mm512_max_ps(_mm512_set1_ps(-kClamp), _mm512_min_ps(_mm512_set1_ps(kClamp), x_in));
  const __mmask16 tiny =
      _mm512_cmp_ps_mask(_mm512_abs_ps(x_in), _mm512_set1_ps(0.0004f), _CMP_LT_OQ);
  const __m512 x2 = _mm512_mul_ps(x, x);
  const __m512 p = _mm512_mul_ps(x, horner(x2, kP));
  const __m512 q = horner(x2, kQ);
  return _mm512_mask_blend_ps(tiny, _mm512_div_ps(p, q), x);
}

// The last vector of a padded buffer may hold one packet of 8 (padded is a multiple of 8).
DEIXIS_AVX512_TARGET inline __mmask16 vector_mask(std::size_t left) noexcept {
  return left >= 16 ? static_cast<__mmask16>(0xffff) : static_cast<__mmask16>(0x00ff);
}

DEIXIS_AVX512_TARGET void logistic_avx512(float* values, std::size_t padded) noexcept {
  for (std::size_t i = 0; i < padded; i += 16) {
    const __mmask16 mask = vector_mask(padded - i);
    const __m512 x = _mm512_maskz_loadu_ps(mask, values + i);
    if (_mm512_cmp_ps_mask(x, _mm512_set1_ps(-9.0f), _CMP_LT_OQ) != 0) {
      // Eigen's own packets for the rare vector with a value below −9 (its e^x branch).
      eigen_logistic(values + i, std::min<std::size_t>(16, padded - i));
      continue;
    }
    _mm512_mask_storeu_ps(values + i, mask, logistic16(x));
  }
}

DEIXIS_AVX512_TARGET void tanh_avx512(float* values, std::size_t padded) noexcept {
  for (std::size_t i = 0; i < padded; i += 16) {
    const __mmask16 mask = vector_mask(padded - i);
    _mm512_mask_storeu_ps(values + i, mask, tanh16(_mm512_maskz_loadu_ps(mask, values + i)));
  }
}

DEIXIS_AVX512_TARGET void gru_gates_avx512(const float* gi, float* gh, float* h,
                                           std::size_t values) noexcept {
  const std::size_t rz_size = 2 * values;
  for (std::size_t i = 0; i < rz_size; i += 16) {
    const __m512 x = _mm512_add_ps(_mm512_loadu_ps(gi + i), _mm512_loadu_ps(gh + i));
    if (_mm512_cmp_ps_mask(x, _mm512_set1_ps(-9.0f), _CMP_LT_OQ) != 0) {
      _mm512_storeu_ps(gh + i, x);
      eigen_logistic(gh + i, 16);  // as logistic_avx512 does
      continue;
    }
    _mm512_storeu_ps(gh + i, logistic16(x));
  }
  const float* reset = gh;
  const float* update = gh + values;
  const float* gh_candidate = gh + rz_size;
  const float* gi_candidate = gi + rz_size;
  for (std::size_t k = 0; k < values; k += 16) {
    const __m512 n =
        tanh16(_mm512_fmadd_ps(_mm512_loadu_ps(reset + k), _mm512_loadu_ps(gh_candidate + k),
                               _mm512_loadu_ps(gi_candidate + k)));
    const __m512 h_old = _mm512_loadu_ps(h + k);
    _mm512_storeu_ps(h + k,
                     _mm512_fmadd_ps(_mm512_loadu_ps(update + k), _mm512_sub_ps(h_old, n), n));
  }
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

using GateLoop = void (*)(float* values, std::size_t padded) noexcept;
#if DEIXIS_AVX512_KERNEL
constexpr GateLoop kLogisticAvx512 = logistic_avx512;
constexpr GateLoop kTanhAvx512 = tanh_avx512;
#else
constexpr GateLoop kLogisticAvx512 = nullptr;
constexpr GateLoop kTanhAvx512 = nullptr;
#endif

// values[0, n) through `avx512` where that is the kernel (and built), else through `build`, the
// padding up to padded_to_packets(n) zeroed first.
void apply_gate(ProductKernel kernel, GateLoop build, GateLoop avx512, float* values,
                std::size_t n) noexcept {
  const std::size_t padded = padded_to_packets(n);
  std::fill(values + n, values + padded, 0.0f);
  const bool wide = kernel == ProductKernel::kAvx512 && avx512 != nullptr;
  (wide ? avx512 : build)(values, padded);
}

}  // namespace

void logistic_in_place(ProductKernel kernel, float* values, std::size_t n) noexcept {
  apply_gate(kernel, eigen_logistic, kLogisticAvx512, values, n);
}

void tanh_in_place(ProductKernel kernel, float* values, std::size_t n) noexcept {
  apply_gate(kernel, eigen_tanh, kTanhAvx512, values, n);
}

void gru_gates_in_lanes(ProductKernel kernel, const float* gi, float* gh, float* h,
                        std::size_t values) noexcept {
#if DEIXIS_AVX512_KERNEL
  if (kernel == ProductKernel::kAvx512 && values % 16 == 0) {
    gru_gates_avx512(gi, gh, h, values);
    return;
  }
#else
  (void)kernel;
#endif
  // `values` is a multiple of kLaneGroup (gates.h), so of any build's packet size too.
  gru_gates_in_packets(gi, gh, h, values);
}

void gru_gates_in_lanes(const float* gi, float* gh, float* h, std::size_t values) noexcept {
  gru_gates_in_lanes(best_product_kernel(), gi, gh, h, values);
}

void logistic_in_place(float* values, std::size_t n) noexcept {
  logistic_in_place(best_product_kernel(), values, n);
}

void tanh_in_place(float* values, std::size_t n) noexcept {
  tanh_in_place(best_product_kernel(), values, n);
}

}  // namespace deixis::nn
