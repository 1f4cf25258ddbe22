// The table note on the FMD encoder (eval/encoder_report.h): the reconstruction errors from the
// encoder's manifest, as deixis-train writes them; a missing manifest, one without the figures
// and a corrupt one each give a line that says so and names the file, never an invented number.

#include "eval/encoder_report.h"

#include <gtest/gtest.h>

#include <fstream>

#include "test_support.h"

namespace deixis::eval {
namespace {

namespace fs = std::filesystem;

fs::path encoder_with_manifest(const fs::path& dir, const std::string& manifest) {
  const fs::path weights = dir / "AutoEncoder.safetensors";
  std::ofstream(weights) << "weights";
  if (!manifest.empty()) {
    std::ofstream(dir / "AutoEncoder.manifest.json") << manifest;
  }
  return weights;
}

TEST(EncoderReport, TheManifestsReconstructionErrorsAreQuoted) {
  deixis::testing::ScratchDir dir;
  const fs::path weights = encoder_with_manifest(dir.path(), R"({
    "schedule": {"epochs": 600},
    "reconstruction": {
      "training": {"position_cm": 0.4123, "rotation_deg": 1.0567, "segments": 36764},
      "validation": {"position_cm": 1.3333, "rotation_deg": 3.9876, "segments": 13100}}})");
  const std::string line = describe_encoder(weights, "right");
  EXPECT_NE(line.find("right hand"), std::string::npos) << line;
  EXPECT_NE(line.find("0.41 cm, 1.06° on the training subject"), std::string::npos) << line;
  EXPECT_NE(line.find("1.33 cm, 3.99° on the validation subjects"), std::string::npos) << line;
  EXPECT_NE(line.find("600 epochs"), std::string::npos) << line;
  // Each hand's encoder is set beside the paper's figures for that hand (§V).
  EXPECT_NE(line.find("paper, right hand: 0.38 cm, 0.97° and 1.29 cm, 3.90°"), std::string::npos)
      << line;
  const std::string left = describe_encoder(weights, "left");
  EXPECT_NE(left.find("paper, left hand: 0.38 cm, 0.95° and 1.57 cm, 3.96°"), std::string::npos)
      << left;
}

TEST(EncoderReport, AFigureTheTrainerCouldNotMeasureIsSaidSo) {
  deixis::testing::ScratchDir dir;
  const fs::path weights = encoder_with_manifest(dir.path(), R"({"reconstruction": {
      "training": {"position_cm": null, "rotation_deg": null, "segments": 10},
      "validation": null}})");
  const std::string line = describe_encoder(weights, "right");
  EXPECT_NE(line.find("reconstruction per frame (not measured) on the training subject"),
            std::string::npos)
      << line;
  EXPECT_EQ(line.find("not a deixis-train manifest"), std::string::npos) << line;
  EXPECT_EQ(line.find("epochs"), std::string::npos) << line;  // no schedule in this manifest
}

TEST(EncoderReport, NoValidationSubjectsLeavesThemOut) {
  deixis::testing::ScratchDir dir;
  const fs::path weights = encoder_with_manifest(dir.path(), R"({"reconstruction": {
      "training": {"position_cm": 0.5, "rotation_deg": 1.5, "segments": 10},
      "validation": null}})");
  const std::string line = describe_encoder(weights, "left");
  EXPECT_NE(line.find("0.50 cm, 1.50° on the training subject"), std::string::npos) << line;
  EXPECT_EQ(line.find("validation subjects"), std::string::npos) << line;
}

TEST(EncoderReport, MissingOldOrCorruptManifestsAreSaidAndNamed) {
  deixis::testing::ScratchDir missing_dir;
  const std::string missing =
      describe_encoder(encoder_with_manifest(missing_dir.path(), ""), "right");
  EXPECT_NE(missing.find("no manifest"), std::string::npos) << missing;
  EXPECT_NE(missing.find("AutoEncoder.manifest.json"), std::string::npos) << missing;

  deixis::testing::ScratchDir old_dir;
  const std::string old =
      describe_encoder(encoder_with_manifest(old_dir.path(), R"({"history": []})"), "right");
  EXPECT_NE(old.find("has no reconstruction figures"), std::string::npos) << old;

  deixis::testing::ScratchDir corrupt_dir;
  const std::string corrupt = describe_encoder(
      encoder_with_manifest(corrupt_dir.path(), "{\"reconstruction\": [1,"), "right");
  EXPECT_NE(corrupt.find("not a deixis-train manifest"), std::string::npos) << corrupt;
  EXPECT_NE(corrupt.find("AutoEncoder.manifest.json"), std::string::npos) << corrupt;
  // A figure that is not a number is a bad manifest too, not a crash.
  deixis::testing::ScratchDir wrong_dir;
  const std::string wrong = describe_encoder(
      encoder_with_manifest(wrong_dir.path(),
                            R"({"reconstruction": {"training": {"position_cm": "a lot"},
                                                   "validation": null}})"),
      "right");
  EXPECT_NE(wrong.find("not a deixis-train manifest"), std::string::npos) << wrong;
}

}  // namespace
}  // namespace deixis::eval
