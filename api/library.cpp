// The library as a whole: its version, ABI check, status names, errors and the data directory.
#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "api/boundary.h"
#include "api/data_dir.h"

namespace deixis::api {

void check_abi(std::uint32_t abi_version) {
  if (abi_version != DEIXIS_ABI_VERSION) {
    throw CallError(DEIXIS_ERROR_ABI,
                    "the caller was built against Deixis ABI " + std::to_string(abi_version) +
                        " and this library is ABI " + std::to_string(DEIXIS_ABI_VERSION) +
                        ": rebuild it against this library's deixis.h");
  }
}

void write_error(deixis_error* error, deixis_status status, const char* message) noexcept {
  if (error == nullptr) {
    return;
  }
  error->status = status;
  std::size_t n = std::strlen(message);
  if (n >= DEIXIS_ERROR_MESSAGE_SIZE) {
    n = DEIXIS_ERROR_MESSAGE_SIZE - 1;
    // Do not cut a UTF-8 sequence in half: back up over continuation bytes.
    while (n > 0 && (static_cast<unsigned char>(message[n]) & 0xC0u) == 0x80u) {
      --n;
    }
  }
  std::memcpy(error->message, message, n);
  error->message[n] = '\0';
}

namespace {

// share/deixis beside the directory this library was loaded from (an installed prefix).
std::filesystem::path installed_data_dir() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&deixis_data_dir), &info) == 0 || info.dli_fname == nullptr) {
    return {};
  }
  // The loader keeps the path it was given, which may hold ".." (a Python module's relative
  // path to the library): resolve it before walking up.
  std::error_code error;
  const std::filesystem::path library = std::filesystem::weakly_canonical(info.dli_fname, error);
  if (error) {
    return {};
  }
  return library.parent_path().parent_path() / "share" / "deixis";
}

bool has_data(const std::filesystem::path& dir) {
  std::error_code ignored;
  return !dir.empty() && std::filesystem::is_directory(dir / "weights", ignored);
}

std::filesystem::path find_data_dir() {
  if (const char* env = std::getenv("DEIXIS_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!has_data(env)) {
      throw Error(std::string("DEIXIS_DATA_DIR=") + env + " has no weights/ directory");
    }
    return env;
  }
  if (const auto installed = installed_data_dir(); has_data(installed)) {
    return installed;
  }
  if (const std::filesystem::path source = DEIXIS_SOURCE_DATA_DIR; has_data(source)) {
    return source;
  }
  throw Error(
      "no Deixis data directory: set DEIXIS_DATA_DIR to one holding weights/ and "
      "avatars/ (an install puts them in <prefix>/share/deixis)");
}

}  // namespace

std::filesystem::path data_dir() {
  return find_data_dir();
}

}  // namespace deixis::api

using namespace deixis::api;

extern "C" {

const char* deixis_version(void) {
  return DEIXIS_LIBRARY_VERSION;
}

uint32_t deixis_abi_version(void) {
  return DEIXIS_ABI_VERSION;
}

const char* deixis_status_name(deixis_status status) {
  switch (status) {
    case DEIXIS_OK:
      return "ok";
    case DEIXIS_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case DEIXIS_ERROR_FILE:
      return "file error";
    case DEIXIS_ERROR_ABI:
      return "ABI mismatch";
    case DEIXIS_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case DEIXIS_ERROR_INTERNAL:
      return "internal error";
  }
  return "unknown status";
}

deixis_status deixis_data_dir(char* buffer, size_t capacity, size_t* length) {
  return guarded(
      DEIXIS_ERROR_FILE,
      [&] {
        const std::string dir = data_dir().string();
        if (length != nullptr) {
          *length = dir.size() + 1;
        }
        require(buffer != nullptr && capacity > dir.size(),
                "deixis_data_dir: the buffer is too small (*length says how large it must be)");
        std::memcpy(buffer, dir.c_str(), dir.size() + 1);
      },
      [](deixis_status, const char*) {});
}

}  // extern "C"
