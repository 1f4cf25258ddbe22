#pragma once
// The one exception type Deixis throws at its boundaries (files, flags, packets at load time).
// Messages name what was wrong and where, e.g.
//   "weights/MPNet.safetensors: tensor 'gru.weight_ih_l0': expected shape [72, 11], found [72,
//   12]".
// Hot paths never throw: they run on inputs that a boundary already validated.

#include <stdexcept>
#include <string>

namespace deixis {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace deixis
