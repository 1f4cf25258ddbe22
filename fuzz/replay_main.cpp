// Replays fuzz inputs without libFuzzer, so that ordinary builds (GCC, with or without ASan and
// UBSan) run a fuzz target over its committed corpus as a test. Every regular file named on the
// command line, and every regular file under each directory named, goes once through
// LLVMFuzzerTestOneInput, in sorted order. A crash is the fuzz target's own report; this program
// fails only when an argument is missing or unreadable, or when it replayed nothing.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

// The inputs an argument names: the file itself, or a directory's regular files, recursively.
bool collect_inputs(const fs::path& argument, std::vector<fs::path>& inputs) {
  std::error_code error;
  if (fs::is_regular_file(argument, error)) {
    inputs.push_back(argument);
    return true;
  }
  if (!fs::is_directory(argument, error)) {
    std::fprintf(stderr, "replay: %s: no such file or directory\n", argument.c_str());
    return false;
  }
  std::vector<fs::path> found;
  for (fs::recursive_directory_iterator it(argument, error), end; !error && it != end;
       it.increment(error)) {
    if (it->is_regular_file(error)) {
      found.push_back(it->path());
    }
  }
  if (error) {
    std::fprintf(stderr, "replay: %s: %s\n", argument.c_str(), error.message().c_str());
    return false;
  }
  std::sort(found.begin(), found.end());  // the same order on every machine
  inputs.insert(inputs.end(), found.begin(), found.end());
  return true;
}

bool read_file(const fs::path& path, std::vector<std::uint8_t>& bytes) {
  std::error_code error;
  const std::uintmax_t size = fs::file_size(path, error);
  if (error) {
    return false;
  }
  bytes.resize(size);
  std::ifstream in(path, std::ios::binary);
  return in && in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: %s CORPUS_DIR_OR_FILE...\n"
                 "Feeds every file (directories: recursively) to the fuzz target once.\n",
                 argv[0]);
    return 2;
  }
  std::vector<fs::path> inputs;
  for (int i = 1; i < argc; ++i) {
    if (!collect_inputs(argv[i], inputs)) {
      return 2;
    }
  }
  std::vector<std::uint8_t> bytes;
  for (const fs::path& input : inputs) {
    if (!read_file(input, bytes)) {
      std::fprintf(stderr, "replay: %s: read failed\n", input.c_str());
      return 2;
    }
    // Named before it runs, so that a crash report can be traced to its input.
    std::fprintf(stderr, "replay: %s (%zu bytes)\n", input.c_str(), bytes.size());
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::printf("replayed %zu inputs\n", inputs.size());
  if (inputs.empty()) {
    std::fprintf(stderr, "replay: no inputs found; an empty corpus tests nothing\n");
    return 1;
  }
  return 0;
}
