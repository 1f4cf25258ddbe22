// What a user of the installed package does (docs/embedding.md): `cmake --install` into a fresh
// prefix, the examples built out of tree against that prefix only (through the CMake package and
// through pkg-config), run, and their output compared with the in-tree translator's on the same
// recording. Also: the installed library finds its shipped data beside itself.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "api/tracking_csv.h"
#include "test_support.h"

namespace deixis::testing {
namespace {

namespace fs = std::filesystem;

// Runs a shell command; its standard output (stderr goes to `log`).
std::string run(const std::string& command, const fs::path& log) {
  const std::string full = command + " 2>>" + log.string();
  FILE* pipe = popen(full.c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "cannot run " << command;
    return {};
  }
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) {
    out += buffer;
  }
  const int status = pclose(pipe);
  if (status != 0) {
    std::ifstream in(log);
    std::stringstream s;
    s << in.rdbuf();
    ADD_FAILURE() << command << "\nexited " << status << "; its log:\n" << s.str();
  }
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    result.push_back(line);
  }
  return result;
}

void expect_same_ticks(const std::vector<std::string>& printed,
                       const std::vector<std::string>& expected, const std::string& program) {
  SCOPED_TRACE(program);
  const auto got = parse_ticks(printed);
  const auto want = parse_ticks(expected);
  ASSERT_EQ(got.size(), want.size());
  ASSERT_GT(got.size(), 100u);
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].tick, want[i].tick);
    EXPECT_EQ(got[i].visible, want[i].visible);
    EXPECT_EQ(got[i].held, want[i].held);
    EXPECT_LT((got[i].fingertip - want[i].fingertip).norm(), 2e-5f) << "tick " << i;
  }
}

TEST(Examples, BuiltAgainstTheInstalledPackageTheyPrintWhatTheInTreeTranslatorComputes) {
  const ScratchDir dir;
  const fs::path prefix = dir.path() / "prefix";
  const fs::path log = dir.path() / "log.txt";
  const fs::path examples = examples_dir();
  const std::string csv = (examples / "data/pointing.csv").string();
  const std::string map = (examples / "data/room.json").string();
  const std::vector<std::string> expected = in_tree_fingertips(csv, map);

  run("cmake --install " DEIXIS_BUILD_DIR " --prefix " + prefix.string(), log);
  ASSERT_TRUE(fs::exists(prefix / "include/deixis/deixis.h"));
  ASSERT_TRUE(fs::exists(prefix / "share/deixis/avatars/default.glb"));

  // The CMake package: find_package(Deixis CONFIG) from the prefix alone.
  const fs::path build = dir.path() / "build";
  run("cmake -S " + examples.string() + " -B " + build.string() + " -G Ninja -DCMAKE_PREFIX_PATH=" +
          prefix.string() + " -DCMAKE_C_COMPILER=" + DEIXIS_EXAMPLE_CC +
          " -DCMAKE_CXX_COMPILER=" + DEIXIS_EXAMPLE_CXX +
          " '-DCMAKE_C_FLAGS=-Wall -Wextra -Werror " DEIXIS_EXAMPLE_FLAGS
          "' '-DCMAKE_CXX_FLAGS=-Wall -Wextra -Werror " DEIXIS_EXAMPLE_FLAGS
          "' '-DCMAKE_EXE_LINKER_FLAGS=" DEIXIS_EXAMPLE_LINK_FLAGS "'",
      log);
  run("cmake --build " + build.string(), log);

  // pkg-config: the C example compiled by hand.
  const std::string pkg = "PKG_CONFIG_PATH=" + (prefix / "lib/pkgconfig").string() + " pkg-config";
  EXPECT_EQ(run(pkg + " --modversion deixis", log), "0.1.0\n");
  std::string datadir = run(pkg + " --variable=datadir deixis", log);
  datadir.erase(datadir.find_last_not_of('\n') + 1);
  EXPECT_EQ(fs::weakly_canonical(datadir), fs::weakly_canonical(prefix / "share/deixis"));
  const fs::path by_hand = dir.path() / "play_tracking_pc";
  run(std::string(DEIXIS_EXAMPLE_CC) + " -std=c11 -Wall -Wextra -Werror " DEIXIS_EXAMPLE_FLAGS " " +
          (examples / "c/play_tracking.c").string() + " -o " + by_hand.string() + " $(" + pkg +
          " --cflags --libs deixis) -lm " DEIXIS_EXAMPLE_LINK_FLAGS,
      log);

  // Run each without the build tree's help: no DEIXIS_DATA_DIR, the library found by the
  // RPATH CMake wrote or by LD_LIBRARY_PATH for the hand-built one.
  const std::string args = " " + csv + " " + map;
  const std::string clean = "env -u DEIXIS_DATA_DIR ";
  const fs::path data_log = dir.path() / "data.txt";
  expect_same_ticks(lines(run(clean + (build / "play_tracking_c").string() + args, data_log)),
                    expected, "play_tracking_c");
  expect_same_ticks(lines(run(clean + (build / "play_tracking_cpp").string() + args, log)),
                    expected, "play_tracking_cpp");
  expect_same_ticks(lines(run(clean + "LD_LIBRARY_PATH=" + (prefix / "lib").string() + " " +
                                  by_hand.string() + args,
                              log)),
                    expected, "play_tracking (pkg-config)");
  // The C example says where its data came from: the prefix, not this source tree.
  std::ifstream in(data_log);
  std::stringstream said;
  said << in.rdbuf();
  EXPECT_NE(said.str().find(fs::weakly_canonical(prefix / "share/deixis").string()),
            std::string::npos)
      << said.str();

#if !defined(DEIXIS_SANITIZED)  // an instrumented library does not load into Python
  // The installed Python module finds the installed library and its data, nothing else.
  const std::string python = clean +
                             "PYTHONPATH=" + (prefix / "lib/python3/dist-packages").string() + " " +
                             DEIXIS_PYTHON3 + " -c 'import deixis; print(deixis.data_dir()); " +
                             "print(deixis.Mpnet().run(__import__(\"numpy\").zeros((30, 11))))'";
  const std::vector<std::string> printed = lines(run(python, log));
  ASSERT_EQ(printed.size(), 2u);
  EXPECT_EQ(fs::weakly_canonical(printed[0]), fs::weakly_canonical(prefix / "share/deixis"));
#endif
}

}  // namespace
}  // namespace deixis::testing
