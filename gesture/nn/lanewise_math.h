#pragma once
// exp and expm1 for the networks' ELUs, each result computed from its own argument alone, by a
// fixed sequence of IEEE operations (multiply-add, multiply, add, compare-and-select,
// exponent-field arithmetic) with no branch taken for a group of values.
//
// Why: the C library's expm1 runs one value at a time, and the ELUs between the MoE experts'
// layers called it for every negative activation, 8 % of a 64-person tick (docs/scaling.md).
// These are a few multiply-adds the compiler vectorises, and a value's result is the same bits
// wherever it sits (in a vector, in a loop's scalar remainder, alone or beside other people's
// values), which keeps a person's translation bit for bit the same alone and in any batch
// (docs/decisions.md, decision 88).
//
// Accuracy (tests/nn/lanewise_math_test.cpp, against double precision): exp within 1.2e-7
// relative over [−87, 88] (Cephes' expf polynomial after a Cody-Waite reduction), expm1 within
// 2.7e-7, far inside the 1e-5 agreement with the authors' PyTorch networks.

#include <bit>
#include <cmath>
#include <cstdint>

namespace deixis::nn::lanewise {

// a·b + c, fused where the build has fused multiply-add (the release build's x86-64-v3), else
// a multiply and an add. Either way the same operation for every value of a build.
inline float multiply_add(float a, float b, float c) noexcept {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

// e^x for x in [−87, 88] (arguments outside are clamped there: e^−87 ≈ 1.6e-38 is the smallest
// result still a normal float, e^88 ≈ 1.7e38 the largest below FLT_MAX). NaN stays NaN.
inline float exp(float x) noexcept {
  x = x < -87.0f ? -87.0f : x;
  x = x > 88.0f ? 88.0f : x;
  // n = round(x / ln 2), by the 1.5·2^23 trick: adding it leaves n in the low mantissa bits.
  constexpr float kShift = 0x1.8p23f;
  const float shifted = multiply_add(x, 1.44269504088896341f, kShift);
  const float n = shifted - kShift;
  // (Unsigned, so that a NaN's garbage bits wrap instead of overflowing.)
  const std::uint32_t n_bits =
      std::bit_cast<std::uint32_t>(shifted) - std::bit_cast<std::uint32_t>(kShift);
  // r = x − n·ln 2 in two parts (Cody-Waite), |r| ≤ ln 2 / 2.
  float r = multiply_add(n, -0.693359375f, x);
  r = multiply_add(n, 2.12194440e-4f, r);
  // e^r = 1 + r + r²·P(r) (Cephes expf).
  float p = 1.9875691500e-4f;
  p = multiply_add(p, r, 1.3981999507e-3f);
  p = multiply_add(p, r, 8.3334519073e-3f);
  p = multiply_add(p, r, 4.1665795894e-2f);
  p = multiply_add(p, r, 1.6666665459e-1f);
  p = multiply_add(p, r, 5.0000001201e-1f);
  const float e_r = multiply_add(p, r * r, r + 1.0f);
  // · 2^n by adding n to the exponent field: e_r is in [0.70, 1.42], so the result stays normal
  // for every n the clamp allows (−126 … 127).
  const float scaled = std::bit_cast<float>(std::bit_cast<std::uint32_t>(e_r) + (n_bits << 23));
  return x == x ? scaled : x;  // NaN in, NaN out
}

// e^x − 1, accurate for small |x| too (the ELU's negative side, torch.nn.ELU uses expm1).
inline float expm1(float x) noexcept {
  // |x| < 0.35: the Taylor series to x^8 (the first term left out is below 2e-8 relative).
  float p = 1.0f / 40320.0f;
  p = multiply_add(p, x, 1.0f / 5040.0f);
  p = multiply_add(p, x, 1.0f / 720.0f);
  p = multiply_add(p, x, 1.0f / 120.0f);
  p = multiply_add(p, x, 1.0f / 24.0f);
  p = multiply_add(p, x, 1.0f / 6.0f);
  p = multiply_add(p, x, 0.5f);
  const float small = multiply_add(p * x, x, x);
  // Elsewhere e^x − 1 loses at most one ulp of e^x ≥ 0.70 to the subtraction: ≤ 2e-7 relative.
  const float large = nn::lanewise::exp(x) - 1.0f;
  return std::fabs(x) < 0.35f ? small : large;
}

}  // namespace deixis::nn::lanewise
