#include "train/interpolate.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <span>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/io/atomic_file.h"
#include "train/manifest.h"

namespace deixis::train {

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
    // read_f32 checks each file holds the tensor as F32 of this shape with finite values, and
    // names the file, tensor and what differs.
    const std::vector<float> from = a.read_f32(t.name, t.shape);
    const std::vector<float> to = b.read_f32(t.name, t.shape);
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
  const std::string text = manifest.dump(2) + "\n";
  write_file_atomically(out_manifest, std::as_bytes(std::span(text)));
}

}  // namespace deixis::train
