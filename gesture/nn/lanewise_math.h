#pragma once
// e^x − 1 for the networks' ELUs, each result computed from its own argument alone, by a
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
// Accuracy (tests/nn/lanewise_math_test.cpp, against double precision, release build): within
// 1.1e-7 relative over [−87, 88] (Cephes' expf polynomial after a Cody-Waite reduction), under
// one float ulp, far inside the 1e-5 agreement with the authors' PyTorch networks.

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

// e^x = 2^n · (1 + q): n = round(x / ln 2), q = e^r − 1 for r = x − n·ln 2, |r| ≤ ln 2 / 2.
struct ExpParts {
  float two_to_n;  // 2^n
  float q;         // e^r − 1
};

// x clamped to [−87, 88] first: e^88 ≈ 1.7e38 is below FLT_MAX, and from −87 on n ≥ −126, so
// 2^n and the results stay normal floats (n = −126 only for x below −86.99, where r ≈ +0.34).
inline ExpParts exp_parts(float x) noexcept {
  x = x < -87.0f ? -87.0f : x;
  x = x > 88.0f ? 88.0f : x;
  // n by the 1.5·2^23 trick: adding it leaves round(x / ln 2) in the low mantissa bits.
  constexpr float kShift = 0x1.8p23f;
  const float shifted = multiply_add(x, 1.44269504088896341f, kShift);
  const float n = shifted - kShift;
  // n as a two's-complement integer (unsigned, so that a NaN's garbage bits wrap).
  const std::uint32_t n_bits =
      std::bit_cast<std::uint32_t>(shifted) - std::bit_cast<std::uint32_t>(kShift);
  // r = x − n·ln 2 in two parts (Cody-Waite: n·0.693359375 is exact).
  float r = multiply_add(n, -0.693359375f, x);
  r = multiply_add(n, 2.12194440e-4f, r);
  // e^r − 1 = r + r²·P(r) (Cephes expf's polynomial).
  float p = 1.9875691500e-4f;
  p = multiply_add(p, r, 1.3981999507e-3f);
  p = multiply_add(p, r, 8.3334519073e-3f);
  p = multiply_add(p, r, 4.1665795894e-2f);
  p = multiply_add(p, r, 1.6666665459e-1f);
  p = multiply_add(p, r, 5.0000001201e-1f);
  const float two_to_n = std::bit_cast<float>((n_bits + 127u) << 23);
  return {two_to_n, multiply_add(p, r * r, r)};
}

// e^x − 1, accurate for small |x| too (the ELU's negative side; torch.nn.ELU uses expm1), with
// arguments clamped to [−87, 88] (exp_parts). ±0 and NaN come back as given, as in the C library
// and torch.
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
  // Elsewhere 2^n · q + (2^n − 1), one rounding: 2^n − 1 is exact for |n| ≤ 24 and within
  // 2^n of −1 below, so subtracting the 1 adds no error (e^x − 1 would multiply e^x's error
  // by up to 3.4, at x = 0.35).
  const ExpParts e = exp_parts(x);
  const float large = multiply_add(e.two_to_n, e.q, e.two_to_n - 1.0f);
  const float result = std::fabs(x) < 0.35f ? small : large;
  return x == 0.0f || x != x ? x : result;  // ±0 and NaN as given
}

}  // namespace deixis::nn::lanewise
