// The layout check (docs/architecture.md, "Folders and libraries"): every #include of another
// folder's header is backed by a CMake link, libraries point one way (each folder has a rank and
// links only to lower ranks), and the runtime never links the synthetic capture or training.
//
// It reads the source tree and the link graph CMake writes at configure time
// (<build>/link_graph.txt, top-level CMakeLists.txt). DEIXIS_LAYOUT_ROOT and
// DEIXIS_LAYOUT_LINK_GRAPH point it at another tree, e.g. an older commit's.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Each folder's rank: a library may link (and include) only folders of a lower rank. Folders
// not listed here that hold a library are an error; tests/, bench/, fuzz/ stand above all.
const std::map<std::string, int> kRank = {
    {"core", 0},    {"gesture", 1}, {"ik", 1},      {"net", 1},   {"xr_test_runtime", 1},
    {"dataset", 1}, {"avatar", 2},  {"capture", 2}, {"train", 2}, {"presence", 2},
    {"render", 3},  {"eval", 3},    {"site", 4},    {"xr", 4},    {"sim", 5},
    {"app", 6},     {"api", 3},     {"mocap", 1},
};
const std::set<std::string> kAboveAll = {"tests", "bench", "fuzz"};
// What runs in a site (headless, simulator-free, headset): it never links these.
const std::set<std::string> kRuntime = {"core",   "gesture",  "ik",   "net", "avatar",
                                        "render", "presence", "site", "xr",  "api"};
const std::set<std::string> kNeverInRuntime = {"capture", "train"};

struct Target {
  std::string name;
  std::string type;
  std::string folder;
  std::vector<fs::path> sources;
  std::vector<std::string> links;
  bool is_library() const { return type.find("LIBRARY") != std::string::npos; }
};

struct Tree {
  fs::path root;
  std::map<std::string, Target> targets;
  std::map<std::string, std::vector<std::string>> libraries_of_folder;
  std::map<fs::path, std::vector<std::string>> targets_of_source;
};

fs::path setting(const char* env, const char* fallback) {
  const char* value = std::getenv(env);
  return value != nullptr && *value != '\0' ? fs::path(value) : fs::path(fallback);
}

// The first component of `path` below `root`, or "" outside it.
std::string folder_of(const fs::path& root, const fs::path& path) {
  const fs::path relative = path.lexically_normal().lexically_relative(root);
  if (relative.empty() || relative == "." || *relative.begin() == "..") {
    return "";  // outside the tree, or its root (build settings: deixis_options, deixis_warnings)
  }
  return relative.begin()->string();
}

Tree read_tree() {
  Tree tree;
  tree.root = fs::weakly_canonical(setting("DEIXIS_LAYOUT_ROOT", DEIXIS_SOURCE_DIR));
  const fs::path graph = setting("DEIXIS_LAYOUT_LINK_GRAPH", DEIXIS_LINK_GRAPH);
  std::ifstream in(graph);
  if (!in) {
    throw std::runtime_error(graph.string() + ": cannot read the link graph");
  }
  Target* current = nullptr;
  fs::path current_dir;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string kind, value;
    words >> kind >> value;
    if (kind == "target") {
      std::string type, dir;
      words >> type >> dir;
      current = &tree.targets[value];
      current->name = value;
      current->type = type;
      current_dir = fs::path(dir);
      current->folder = folder_of(tree.root, current_dir);
    } else if (kind == "source" && current != nullptr) {
      fs::path source(value);
      if (source.is_relative()) {
        source = current_dir / source;
      }
      current->sources.push_back(source.lexically_normal());
    } else if (kind == "link" && current != nullptr) {
      current->links.push_back(value);
    }
  }
  for (const auto& [name, target] : tree.targets) {
    if (target.is_library() && !target.folder.empty()) {
      tree.libraries_of_folder[target.folder].push_back(name);
    }
    for (const fs::path& source : target.sources) {
      tree.targets_of_source[source].push_back(name);
    }
  }
  return tree;
}

// Every project target `name` links, directly or through others (itself included).
std::set<std::string> closure(const Tree& tree, const std::string& name) {
  std::set<std::string> seen;
  std::vector<std::string> stack = {name};
  while (!stack.empty()) {
    const std::string next = stack.back();
    stack.pop_back();
    const auto found = tree.targets.find(next);
    if (found == tree.targets.end() || !seen.insert(next).second) {
      continue;
    }
    for (const std::string& link : found->second.links) {
      stack.push_back(link);
    }
  }
  return seen;
}

bool links_any(const Tree& tree, const std::string& target, const std::vector<std::string>& any) {
  const std::set<std::string> reach = closure(tree, target);
  for (const std::string& library : any) {
    if (reach.contains(library)) {
      return true;
    }
  }
  return false;
}

bool links_folder(const Tree& tree, const std::string& target, const std::string& folder) {
  const auto libraries = tree.libraries_of_folder.find(folder);
  return libraries != tree.libraries_of_folder.end() && links_any(tree, target, libraries->second);
}

// The targets that compile the header's own .cpp (core/target_map.cpp for core/target_map.h):
// an include of it needs one of those, not just any library of its folder.
std::vector<std::string> owners_of_header(const Tree& tree, const std::string& path) {
  fs::path source = tree.root / path;
  source.replace_extension(".cpp");
  const auto found = tree.targets_of_source.find(source.lexically_normal());
  return found == tree.targets_of_source.end() ? std::vector<std::string>{} : found->second;
}

bool skipped_directory(const fs::path& path) {
  const std::string name = path.filename().string();
  return name == "build" || name == "node_modules" || name == "out" || name.starts_with(".");
}

std::vector<fs::path> source_files(const fs::path& root) {
  std::vector<fs::path> files;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator();
       ++it) {
    if (it->is_directory() && skipped_directory(it->path())) {
      it.disable_recursion_pending();
      continue;
    }
    const std::string extension = it->path().extension().string();
    if (it->is_regular_file() && (extension == ".h" || extension == ".cpp")) {
      files.push_back(it->path().lexically_normal());
    }
  }
  return files;
}

// The folders a file includes from ("core" for #include "core/math/pose.h"), with line numbers.
struct Include {
  int line = 0;
  std::string folder;  // "core"
  std::string path;    // "core/math/pose.h"
};

// `#include "folder/rest"` on a line, by hand: GCC 12 warns (-Wmaybe-uninitialized) inside
// std::regex in the sanitizer build.
std::optional<Include> include_on(const std::string& line, int number) {
  std::size_t at = line.find_first_not_of(" \t");
  if (at == std::string::npos || line[at] != '#') {
    return std::nullopt;
  }
  at = line.find_first_not_of(" \t", at + 1);
  if (at == std::string::npos || line.compare(at, 7, "include") != 0) {
    return std::nullopt;
  }
  const std::size_t open = line.find('"', at + 7);
  const std::size_t close = open == std::string::npos ? open : line.find('"', open + 1);
  if (close == std::string::npos) {
    return std::nullopt;
  }
  const std::string path = line.substr(open + 1, close - open - 1);
  const std::size_t slash = path.find('/');
  if (slash == std::string::npos || slash == 0) {
    return std::nullopt;
  }
  return Include{number, path.substr(0, slash), path};
}

std::vector<Include> included_folders(const fs::path& file) {
  std::vector<Include> folders;
  std::ifstream in(file);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (const std::optional<Include> include = include_on(line, number)) {
      folders.push_back(*include);
    }
  }
  return folders;
}

std::string join(const std::vector<std::string>& problems) {
  std::string text;
  for (const std::string& problem : problems) {
    text += "\n  " + problem;
  }
  return text;
}

TEST(Layout, EveryIncludeOfAnotherFolderIsBackedByALink) {
  const Tree tree = read_tree();
  std::vector<std::string> problems;
  for (const fs::path& file : source_files(tree.root)) {
    const std::string folder = folder_of(tree.root, file);
    const std::string where = file.lexically_relative(tree.root).string();
    // A .cpp is checked for every target that compiles it; a header for its folder's targets.
    std::vector<std::string> users;
    if (const auto found = tree.targets_of_source.find(file);
        found != tree.targets_of_source.end()) {
      users = found->second;
    } else if (file.extension() == ".cpp") {
      continue;  // compiled by no target (the link graph sees only what CMake builds)
    } else {
      for (const auto& [name, target] : tree.targets) {
        if (target.folder == folder) {
          users.push_back(name);
        }
      }
    }
    for (const auto& [line, included, path] : included_folders(file)) {
      if (included == folder || !fs::is_directory(tree.root / included)) {
        continue;  // its own folder, or a third-party header such as "nlohmann/json.hpp"
      }
      if (fs::exists(tree.root / folder / path)) {
        continue;  // a header of its own folder's (tests/app/... included as "app/...")
      }
      const std::string at = where + ":" + std::to_string(line) + " includes " + included + "/";
      if (!tree.libraries_of_folder.contains(included)) {
        problems.push_back(at + ", a folder with no library to link");
        continue;
      }
      if (users.empty()) {
        problems.push_back(at + ", but no target of " + folder + "/ exists to link it");
        continue;
      }
      const bool header = file.extension() == ".h";
      const std::vector<std::string> owners = owners_of_header(tree, path);
      bool backed = !header;
      for (const std::string& user : users) {
        const bool links =
            owners.empty() ? links_folder(tree, user, included) : links_any(tree, user, owners);
        if (header && links) {
          backed = true;
        }
        if (!header && !links) {
          problems.push_back(at + path.substr(included.size() + 1) + ", but " + user +
                             " links no library that builds it");
          backed = true;  // reported per target
        }
      }
      if (!backed) {
        problems.push_back(at + ", but no target of " + folder + "/ links a library of it");
      }
    }
  }
  EXPECT_TRUE(problems.empty()) << problems.size()
                                << " include(s) not backed by a link:" << join(problems);
}

TEST(Layout, LibrariesLinkOnlyDownwards) {
  const Tree tree = read_tree();
  std::vector<std::string> problems;
  for (const auto& [name, target] : tree.targets) {
    if (target.folder.empty() || kAboveAll.contains(target.folder)) {
      continue;
    }
    const auto rank = kRank.find(target.folder);
    if (rank == kRank.end()) {
      problems.push_back(target.folder + "/ (" + name +
                         ") has no place in the layout's ranks (docs/architecture.md)");
      continue;
    }
    for (const std::string& link : target.links) {
      const auto linked = tree.targets.find(link);
      if (linked == tree.targets.end() || linked->second.folder == target.folder ||
          linked->second.folder.empty()) {
        continue;
      }
      const auto linked_rank = kRank.find(linked->second.folder);
      if (linked_rank == kRank.end() || linked_rank->second >= rank->second) {
        problems.push_back(name + " (" + target.folder + "/, rank " + std::to_string(rank->second) +
                           ") links " + link + " (" + linked->second.folder + "/" +
                           (linked_rank == kRank.end()
                                ? ", unranked"
                                : ", rank " + std::to_string(linked_rank->second)) +
                           ")");
      }
    }
  }
  EXPECT_TRUE(problems.empty()) << problems.size()
                                << " link(s) against the layout:" << join(problems);
}

TEST(Layout, TheRuntimeNeverLinksTheCaptureOrTraining) {
  const Tree tree = read_tree();
  std::vector<std::string> problems;
  for (const auto& [name, target] : tree.targets) {
    if (!target.is_library() || !kRuntime.contains(target.folder)) {
      continue;
    }
    for (const std::string& reached : closure(tree, name)) {
      const std::string& folder = tree.targets.at(reached).folder;
      if (kNeverInRuntime.contains(folder)) {
        problems.push_back(name + " (" + target.folder + "/) links " + reached + " (" + folder +
                           "/)");
      }
    }
  }
  EXPECT_TRUE(problems.empty()) << problems.size()
                                << " runtime librar(ies) linking tools:" << join(problems);
}

TEST(Layout, HeadlessSitesLinkNoWindowOrGui) {
  // Host, join and the headset run without a display: nothing they link opens a window (GLFW)
  // or draws a panel (ImGui). The window has a library of its own, for the simulator.
  const Tree tree = read_tree();
  std::vector<std::string> problems;
  for (const auto& [name, target] : tree.targets) {
    if (!target.is_library() || !kRuntime.contains(target.folder) || name.ends_with("_window")) {
      continue;
    }
    for (const std::string& reached : closure(tree, name)) {
      for (const std::string& link : tree.targets.at(reached).links) {
        std::string lower = link;
        std::transform(lower.begin(), lower.end(), lower.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (lower.find("glfw") != std::string::npos || lower.find("imgui") != std::string::npos) {
          problems.push_back(name + " links " + link +
                             (reached == name ? "" : " through " + reached));
        }
      }
    }
  }
  EXPECT_TRUE(problems.empty()) << problems.size()
                                << " headless librar(ies) with a window:" << join(problems);
}

TEST(Layout, TheLinkGraphNamesTheLibraries) {
  // Guards the check itself: a link graph that lost its targets would pass everything above.
  const Tree tree = read_tree();
  for (const char* folder : {"core", "gesture", "ik", "net", "presence", "render", "site"}) {
    EXPECT_TRUE(tree.libraries_of_folder.contains(folder)) << folder << "/ has no library";
  }
  EXPECT_FALSE(source_files(tree.root).empty());
}

}  // namespace
