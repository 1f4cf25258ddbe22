#pragma once
// The GRUs' gate functions over whole buffers of pre-activations: the logistic of the reset and
// update gates and the tanh of the candidate state (gru.h, step_batch and step_lanes).
//
// Every value goes through Eigen 3.4's packet logistic and tanh (rational approximations with one
// division a value), never Eigen's scalar path, which rounds differently (it has no fused
// multiply-adds). Where the CPU has AVX-512 the same operations run sixteen values at a time,
// written out with intrinsics (gates.cpp): the same fused multiply-adds, minimum, maximum, compare,
// select and IEEE division on each value in the same order, so the same bits as Eigen's 8-float
// packets of the build (x86-64-v3), checked value by value over every float of the functions'
// ranges (tests/nn/gates_test.cpp). Why: Eigen picks its packets when it is compiled, and the
// build targets AVX2; the division, which does not get faster per value with wider vectors, then
// overlaps twice the multiply-adds (docs/scaling.md, decision 94).

#include <Eigen/Core>
#include <cstddef>

#include "gesture/nn/batch.h"

namespace deixis::nn {

// The gates run in whole packets of the build's vector unit (8 floats with AVX2), and
// padded_to_packets(n) floats hold n values with no remainder.
inline constexpr std::size_t kGatePacketFloats =
    static_cast<std::size_t>(Eigen::internal::packet_traits<float>::size);

constexpr std::size_t padded_to_packets(std::size_t n) noexcept {
  return (n + kGatePacketFloats - 1) / kGatePacketFloats * kGatePacketFloats;
}

// values[0, n) ← logistic(values), resp. tanh(values), in place. The padding up to
// padded_to_packets(n) is zeroed and evaluated too, so `values` must hold that many floats. Each
// result depends on its own value alone, so a person's gates are the same bits wherever their
// values sit in the buffer. No allocation. With a kernel: the products' choice (batch.h); it must
// be available.
void logistic_in_place(float* values, std::size_t n) noexcept;
void tanh_in_place(float* values, std::size_t n) noexcept;
void logistic_in_place(ProductKernel kernel, float* values, std::size_t n) noexcept;
void tanh_in_place(ProductKernel kernel, float* values, std::size_t n) noexcept;

// The rest of one GRU step with people in lanes (GruLayer::step_lanes), once both projections
// are known: gi = W_ih·x + b_ih and gh = W_hh·h + b_hh, each 3·`values` floats (rows r | z | n,
// value j of person p at j·lanes + p), `values` = Hidden × lanes, a multiple of kLaneGroup. Then
//   r|z = σ(gi_rz + gh_rz),   n = tanh(gi_n + r ⊙ gh_n),   h ← n + z ⊙ (h − n)
// with the same operations on every value as GruLayer::step_batch (a fused multiply-add each for
// n's argument and for h), so a person's bits are the same in either layout. gh is overwritten.
// In one pass over r|z and one over n and h (sixteen values at a time with AVX-512, the build's
// packets otherwise): the sums and multiply-adds ride along with the gates' divisions. No
// allocation.
void gru_gates_in_lanes(const float* gi, float* gh, float* h, std::size_t values) noexcept;
void gru_gates_in_lanes(ProductKernel kernel, const float* gi, float* gh, float* h,
                        std::size_t values) noexcept;

}  // namespace deixis::nn
