#include "eval/encoder_report.h"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

namespace deixis::eval {
namespace {

namespace fs = std::filesystem;

std::string errors_of(const nlohmann::json& e) {
  char text[80];
  std::snprintf(text, sizeof text, "%.2f cm, %.2f°", e.at("position_cm").get<double>(),
                e.at("rotation_deg").get<double>());
  return text;
}

}  // namespace

std::string describe_encoder(const fs::path& encoder_weights, const std::string& hand) {
  std::string line = "FMD encoder, " + hand + " hand (" + encoder_weights.string() + "): ";
  const fs::path manifest_path =
      encoder_weights.parent_path() / (encoder_weights.stem().string() + ".manifest.json");
  std::ifstream in(manifest_path);
  if (!in) {
    return line + "no manifest (" + manifest_path.string() +
           "), so its reconstruction errors are not known.";
  }
  try {
    const nlohmann::json manifest = nlohmann::json::parse(in);
    const auto found = manifest.find("reconstruction");
    if (found == manifest.end()) {
      return line + manifest_path.string() +
             " has no reconstruction figures (written by an older deixis-train; rerunning its "
             "command re-exports with them).";
    }
    line +=
        "reconstruction per frame " + errors_of(found->at("training")) + " on the training subject";
    if (!found->at("validation").is_null()) {
      line += ", " + errors_of(found->at("validation")) + " on the validation subjects";
    }
    return line + " (paper, right hand: 0.38 cm, 0.97° and 1.29 cm, 3.90°; " +
           std::to_string(manifest.value("schedule", nlohmann::json::object()).value("epochs", 0)) +
           " epochs).";
  } catch (const nlohmann::json::exception& e) {
    return line + manifest_path.string() + ": not a deixis-train manifest (" + e.what() + ").";
  }
}

}  // namespace deixis::eval
