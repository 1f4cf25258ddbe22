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

}  // namespace deixis::nn
