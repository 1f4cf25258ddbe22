#include "eval/encoder_report.h"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "gesture/nn/motion_encoder.h"

namespace deixis::eval {
namespace {

namespace fs = std::filesystem;

// "0.41 cm, 1.06°"; a figure the trainer could not measure is written as null (NaN).
std::string errors_of(const nlohmann::json& e) {
  const nlohmann::json& cm = e.at("position_cm");
  const nlohmann::json& deg = e.at("rotation_deg");
  if (cm.is_null() || deg.is_null()) {
    return "(not measured)";
  }
  char text[80];
  std::snprintf(text, sizeof text, "%.2f cm, %.2f°", cm.get<double>(), deg.get<double>());
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
    const nn::PaperReconstruction& paper =
        hand == "left" ? nn::kPaperReconstructionLeft : nn::kPaperReconstructionRight;
    char text[120];
    std::snprintf(text, sizeof text, " (paper, %s hand: %.2f cm, %.2f° and %.2f cm, %.2f°)",
                  hand == "left" ? "left" : "right", paper.training_cm, paper.training_deg,
                  paper.validation_cm, paper.validation_deg);
    line += text;
    const int epochs = manifest.value("schedule", nlohmann::json::object()).value("epochs", 0);
    if (epochs > 0) {
      line += "; " + std::to_string(epochs) + " epochs";
    }
    return line + ".";
  } catch (const nlohmann::json::exception& e) {
    return line + manifest_path.string() + ": not a deixis-train manifest (" + e.what() + ").";
  }
}

}  // namespace deixis::eval
