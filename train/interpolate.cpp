#include "train/interpolate.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/error.h"
#include "train/manifest.h"

namespace deixis::train {

namespace {

std::string shape_text(const std::vector<std::int64_t>& shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    s += (i > 0 ? ", " : "") + std::to_string(shape[i]);
  }
  return s + "]";
}

// read_f32 refuses non-finite values, naming the file, tensor and element.
std::vector<float> values_of(const SafetensorsFile& file, const TensorInfo& t) {
  if (t.dtype != DType::kF32) {
    throw Error(file.source() + ": tensor '" + t.name + "' is not F32");
  }
  return file.read_f32(t.name, t.shape);
}

// b's tensor of a's tensor's name, checked to be the same shape.
const TensorInfo& counterpart(const SafetensorsFile& b, const SafetensorsFile& a,
                              const TensorInfo& t) {
  for (const TensorInfo& u : b.tensors()) {
    if (u.name == t.name) {
      if (u.shape != t.shape) {
        throw Error(b.source() + ": tensor '" + t.name + "' has shape " + shape_text(u.shape) +
                    ", " + a.source() + " has " + shape_text(t.shape));
      }
      return u;
    }
  }
  throw Error(b.source() + ": tensor '" + t.name + "' missing (" + a.source() + " has it)");
}

}  // namespace

SafetensorsWriter interpolate_weights(const SafetensorsFile& a, const SafetensorsFile& b,
                                      double alpha) {
  if (!(alpha >= 0.0 && alpha <= 1.0)) {
    throw Error("interpolation: alpha must be in [0, 1], got " + std::to_string(alpha));
  }
  if (a.tensors().size() != b.tensors().size()) {
    throw Error(b.source() + ": " + std::to_string(b.tensors().size()) + " tensors, " + a.source() +
                " has " + std::to_string(a.tensors().size()));
  }
  SafetensorsWriter out;
  for (const auto& [key, value] : b.metadata()) {
    out.set_metadata(key, value);
  }
  std::ostringstream alpha_text;
  alpha_text << alpha;
  out.set_metadata("interpolation_alpha", alpha_text.str());
  const auto weight = static_cast<float>(alpha);
  for (const TensorInfo& t : a.tensors()) {
    const std::vector<float> from = values_of(a, t);
    const std::vector<float> to = values_of(b, counterpart(b, a, t));
    std::vector<float> blend(from.size());
    for (std::size_t i = 0; i < from.size(); ++i) {
      blend[i] = (1.0f - weight) * from[i] + weight * to[i];
    }
    out.add_f32(t.name, t.shape, blend);
  }
  return out;
}

void write_interpolation(const std::filesystem::path& a, const std::filesystem::path& b,
                         double alpha, const std::filesystem::path& out) {
  const SafetensorsWriter blend =
      interpolate_weights(SafetensorsFile::read(a), SafetensorsFile::read(b), alpha);
  nlohmann::json manifest = nlohmann::json::object();
  const std::filesystem::path b_manifest = b.parent_path() / (b.stem().string() + ".manifest.json");
  if (std::filesystem::exists(b_manifest)) {
    std::ifstream in(b_manifest);
    try {
      manifest = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      throw Error(b_manifest.string() + ": not a manifest (" + e.what() + ")");
    }
  }
  manifest["weights"] = out.filename().string();
  manifest["interpolation"] = {{"alpha", alpha},
                               {"from", {{"file", a.string()}, {"sha256", sha256_file(a)}}},
                               {"to", {{"file", b.string()}, {"sha256", sha256_file(b)}}},
                               {"formula", "(1 - alpha) * from + alpha * to, tensor by tensor"}};
  if (!out.parent_path().empty()) {
    std::filesystem::create_directories(out.parent_path());
  }
  blend.write(out);
  const std::filesystem::path out_manifest =
      out.parent_path() / (out.stem().string() + ".manifest.json");
  std::ofstream file(out_manifest);
  file << manifest.dump(2) << "\n";
  if (!file) {
    throw Error(out_manifest.string() + ": cannot write");
  }
}

}  // namespace deixis::train
