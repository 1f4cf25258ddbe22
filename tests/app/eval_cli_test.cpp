// `deixis eval` as a user runs it (the built command, a real process): test sets made by
// `deixis capture generate`, a quick evaluation that exits 0 and writes tables.md, results.json and
// fig5.png with the tables on standard output; data of the training subject refused with exit 2
// naming the file; missing test sets refused with exit 2 naming the directory and the command
// that makes them; bad flags exit 2 naming the flag; --bvh alone measures Debian's recordings in a
// section of its own without any test set, and a bad recording exits 2 naming file:line.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "app/deixis_child.h"
#include "test_support.h"

namespace deixis::app {
namespace {

namespace fs = std::filesystem;

// A small test set for subject 161 (5 % of the protocol's sequence counts).
fs::path make_test_set(const fs::path& dir) {
  Deixis capture({"capture", "generate", "--sets", "test", "--subjects", "161", "--count-scale",
                  "0.05", "-o", (dir / "data").string()});
  EXPECT_EQ(capture.wait(), 0) << capture.err();
  return dir / "data";
}

TEST(EvalCli, AQuickEvaluationWritesTheTables) {
#ifdef DEIXIS_SANITIZED
  GTEST_SKIP() << "every network of every table: minutes under ASan; the release suite runs it";
#endif
  deixis::testing::ScratchDir dir;
  const fs::path data = make_test_set(dir.path());
  const fs::path out = dir.path() / "eval";
  // With a recording as well (when Debian's is installed), its section comes after the
  // synthetic tables, apart from them.
  const fs::path bvh = "/usr/share/assimp/models/BVH/Boxing_Toes.bvh";
  std::vector<std::string> args = {
      "eval", "--quick", "--data",     data.string(), "--subjects",
      "161",  "--out",   out.string(), "--weights",   "authors=" + weights_dir()};
  if (fs::exists(bvh)) {
    args.insert(args.end(), {"--bvh", bvh.string()});
  }
  Deixis eval(args);
  ASSERT_EQ(eval.wait(), 0) << eval.err();
  for (const char* file : {"tables.md", "results.json", "fig5.png"}) {
    EXPECT_GT(fs::file_size(out / file), 100u) << file;
  }
  EXPECT_NE(eval.out().find("Table I"), std::string::npos) << eval.out();
  const nlohmann::json results = nlohmann::json::parse(std::ifstream(out / "results.json"));
  EXPECT_EQ(results["subjects"], nlohmann::json({"161"}));
  if (fs::exists(bvh)) {
    const std::size_t real = eval.out().find("# Real motion (BVH)");
    ASSERT_NE(real, std::string::npos) << eval.out();
    EXPECT_GT(real, eval.out().rfind("## Table V.")) << "the synthetic tables come first";
    EXPECT_GT(eval.out().find("| Boxing_Toes"), real) << "no recording's row among the synthetic";
    EXPECT_EQ(results["real_motion"]["recordings"], nlohmann::json({"Boxing_Toes.bvh"}));
    for (const nlohmann::json& table : results["tables"]) {
      EXPECT_FALSE(table["id"].get<std::string>().starts_with("R")) << table["id"];
    }
  }
}

TEST(EvalCli, TheTrainingSubjectsDataIsRefused) {
  deixis::testing::ScratchDir dir;
  Deixis capture({"capture", "generate", "--sets", "train", "--count-scale", "0.02", "-o",
                  (dir.path() / "data").string()});
  ASSERT_EQ(capture.wait(), 0) << capture.err();
  // The training file under a test subject's name: its metadata still says what it is.
  fs::rename(dir.path() / "data/train_right.safetensors", dir.path() / "data/test_161.safetensors");
  Deixis eval({"eval", "--quick", "--data", (dir.path() / "data").string(), "--subjects", "161",
               "--out", (dir.path() / "eval").string()});
  EXPECT_EQ(eval.wait(), 2);
  EXPECT_NE(eval.err().find("test_161.safetensors"), std::string::npos) << eval.err();
  EXPECT_FALSE(fs::exists(dir.path() / "eval/results.json"));
}

// The fix an error suggests: the command line after "\n  " up to the next line break, split at
// spaces (the scratch paths have none), without the program.
std::vector<std::string> suggested_arguments(const std::string& err) {
  const std::size_t start = err.find("\n  ");
  if (start == std::string::npos) {
    ADD_FAILURE() << "no command in: " << err;
    return {};
  }
  std::istringstream line(err.substr(start + 3, err.find('\n', start + 3) - start - 3));
  std::vector<std::string> words;
  for (std::string word; line >> word;) {
    words.push_back(word);
  }
  EXPECT_EQ(words.empty() ? "" : words.front(), DEIXIS_EXE);
  return {words.begin() + (words.empty() ? 0 : 1), words.end()};
}

TEST(EvalCli, MissingTestSetsNameTheDirectoryAndTheCommandThatMakesThem) {
  deixis::testing::ScratchDir dir;
  const fs::path missing = dir.path() / "no-data";
  const fs::path empty = dir.path() / "empty";
  fs::create_directories(empty);
  const std::string make = std::string(DEIXIS_EXE) + " capture generate --sets test -o ";
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {missing, "no such directory"}, {empty, "no test_<subject>.safetensors in it"}};
  for (const auto& [data, what] : cases) {
    SCOPED_TRACE(data.string());
    Deixis eval({"eval", "--quick", "--data", data.string(), "--out",
                 (dir.path() / "eval").string(), "--weights", "authors=" + weights_dir()});
    EXPECT_EQ(eval.wait(), 2);
    EXPECT_NE(eval.err().find(data.string() + ": " + what), std::string::npos) << eval.err();
    EXPECT_NE(eval.err().find(make + data.string()), std::string::npos) << eval.err();
    EXPECT_FALSE(fs::exists(dir.path() / "eval/results.json"));
  }
  // Without --data: the default directory, out/data in the repository (only while it is not there).
  const fs::path default_data = deixis::testing::source_dir() / "out/data";
  if (!fs::exists(default_data)) {
    Deixis eval({"eval", "--quick", "--out", (dir.path() / "eval").string(), "--weights",
                 "authors=" + weights_dir()});
    EXPECT_EQ(eval.wait(), 2);
    EXPECT_NE(eval.err().find(make + default_data.lexically_normal().string()), std::string::npos)
        << eval.err();
  }
  // The command named makes what was missing.
  Deixis eval({"eval", "--data", missing.string(), "--weights", "authors=" + weights_dir()});
  ASSERT_EQ(eval.wait(), 2);
  Deixis capture(suggested_arguments(eval.err()));
  ASSERT_EQ(capture.wait(), 0) << capture.err();
  for (const char* subject : {"161", "172", "173", "174", "180"}) {
    EXPECT_TRUE(fs::exists(missing / ("test_" + std::string(subject) + ".safetensors"))) << subject;
  }
}

TEST(EvalCli, BadFlagsExitTwoNamingThem) {
  const std::vector<BadInput> cases = {
      {{"eval", "--weights", "nolabel"}, "--weights"},
      {{"eval", "--data", "/nonexistent/dir"}, "--data"},
      {{"eval", "--frobnicate"}, "--frobnicate"},
  };
  expect_refused(cases);
}

const fs::path kDebianBvh = "/usr/share/assimp/models/BVH";

TEST(EvalCli, BvhAloneMeasuresRealMotionWithoutTestSets) {
  const fs::path file = kDebianBvh / "Boxing_Toes.bvh";
  if (!fs::exists(file)) {
    GTEST_SKIP() << "no " << file << " (Debian's assimp-testmodels; tools/install-deps)";
  }
  deixis::testing::ScratchDir dir;
  const fs::path out = dir.path() / "eval";
  // The default --data (out/data) need not exist: nothing synthetic runs.
  Deixis eval({"eval", "--bvh", file.string(), "--out", out.string(), "--weights",
               "authors=" + weights_dir(), "--weights",
               "deixis=" + (deixis::testing::source_dir() / "assets/weights").string()});
  ASSERT_EQ(eval.wait(), 0) << eval.err();
  EXPECT_NE(eval.out().find("# Real motion (BVH)"), std::string::npos) << eval.out();
  EXPECT_EQ(eval.out().find("Table I."), std::string::npos) << "no synthetic table";
  EXPECT_FALSE(fs::exists(out / "fig5.png"));
  const nlohmann::json results = nlohmann::json::parse(std::ifstream(out / "results.json"));
  const nlohmann::json& real = results["real_motion"];
  EXPECT_EQ(real["recordings"], nlohmann::json({"Boxing_Toes.bvh"}));
  EXPECT_TRUE(results["tables"].empty());
  ASSERT_EQ(real["tables"].size(), 4u);
  // (c): only our set is compared with the authors', and its differences are in [0, 1].
  const nlohmann::json& agreement = real["tables"][3]["rows"];
  ASSERT_EQ(agreement.size(), 1u);
  EXPECT_EQ(agreement[0]["weights"], "deixis");
  for (const nlohmann::json& d : agreement[0]["per_recording"]["Boxing_Toes.bvh"]) {
    ASSERT_TRUE(d.is_number());
    EXPECT_GE(d.get<double>(), 0.0);
    EXPECT_LE(d.get<double>(), 1.0);
  }
  // (a) second by second for both sets: one value per second of the 30.7 s recording.
  ASSERT_EQ(real["following_per_second"].size(), 2u);
  EXPECT_EQ(real["following_per_second"][0]["hand_cm"].size(), 31u);
}

TEST(EvalCli, ABadBvhFileExitsTwoNamingFileAndLine) {
  deixis::testing::ScratchDir dir;
  const fs::path file = dir.path() / "bad.bvh";
  std::ofstream(file) << "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 zero\n}\n";
  Deixis eval({"eval", "--bvh", file.string(), "--out", (dir.path() / "eval").string(), "--weights",
               "authors=" + weights_dir()});
  EXPECT_EQ(eval.wait(), 2);
  EXPECT_NE(eval.err().find(file.string() + ":4:"), std::string::npos) << eval.err();
  EXPECT_FALSE(fs::exists(dir.path() / "eval/results.json"));
  Deixis missing({"eval", "--bvh", (dir.path() / "none.bvh").string()});
  EXPECT_EQ(missing.wait(), 2);
  EXPECT_NE(missing.err().find("--bvh"), std::string::npos) << missing.err();
}

TEST(EvalCli, HelpMentionsBvh) {
  Deixis help({"eval", "--help"});
  ASSERT_EQ(help.wait(), 0) << help.err();
  EXPECT_NE(help.out().find("--bvh"), std::string::npos) << help.out();
  EXPECT_NE(help.out().find("Real motion (BVH)"), std::string::npos) << help.out();
}

}  // namespace
}  // namespace deixis::app
