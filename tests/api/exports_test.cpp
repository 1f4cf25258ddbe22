// libdeixis.so exports exactly the functions its header declares, by the explicit list of
// api/exports.map: the three agree, and nothing of the runtime's C++ leaks out.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "test_support.h"

namespace deixis::testing {
namespace {

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::set<std::string> matches(const std::string& text, const std::regex& pattern) {
  std::set<std::string> names;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    names.insert((*it)[1]);
  }
  return names;
}

TEST(CApiExports, HeaderListAndLibraryAgree) {
  const std::set<std::string> declared =
      matches(read(source_dir() / "include/deixis/deixis.h"),
              std::regex(R"(DEIXIS_API[^;]*?\b(deixis_[a-z0-9_]+)\()"));
  const std::set<std::string> listed =
      matches(read(source_dir() / "api/exports.map"),
              std::regex(R"(^\s+(deixis_[a-z0-9_]+);)", std::regex::multiline));
  EXPECT_GT(declared.size(), 40u);
  EXPECT_EQ(declared, listed);

  const std::string command = std::string("nm -D --defined-only ") + DEIXIS_CAPI_FILE;
  FILE* nm = popen(command.c_str(), "r");
  ASSERT_NE(nm, nullptr);
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, nm) != nullptr) {
    output += buffer;
  }
  ASSERT_EQ(pclose(nm), 0) << command;
  std::set<std::string> exported;
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string address, type, name;
    fields >> address >> type >> name;
    if (name.empty()) {  // an absolute symbol without address: the version node
      name = type;
    }
    name = name.substr(0, name.find('@'));
    if (name != "DEIXIS_0") {
      exported.insert(name);
    }
  }
  EXPECT_EQ(exported, declared) << output;
}

}  // namespace
}  // namespace deixis::testing
