// libFuzzer target for parse_site_config (site/site_config.h): a site's configuration is a file
// that may come from anywhere, and its site name goes on the wire in the hello. Every input must
// either parse into a configuration whose site name the wire accepts, or be refused with a
// deixis::Error naming the file. Relative paths resolve against the repository's assets/sites/ (so
// the seeds' target maps load and the fuzzer reaches the placements and the virtual user's script).
// Seeds (fuzz/corpus/site_config/): the demo sites (one played by a BVH recording, read from
// Debian's assimp-testmodels where installed) and hostile files.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/io/text_rules.h"
#include "site/site_config.h"

namespace {

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "site_config_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

// <repository>/assets/sites, from this source file's own path (CMake compiles it by absolute path).
const std::filesystem::path& assets() {
  static const std::filesystem::path dir =
      std::filesystem::path(__FILE__).parent_path().parent_path() / "assets" / "sites";
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const deixis::site::SiteConfig config =
        deixis::site::parse_site_config(text, "fuzz-input.json", assets());
    check(!config.site.empty() && config.site.size() <= deixis::kMaxNameBytes &&
              deixis::is_wire_text(config.site),
          "the site name is wire text");
    if (config.virtual_user) {
      // A synthetic subject performs a script; a recording (docs/bvh.md) plays and has none.
      const deixis::site::VirtualUser& user = *config.virtual_user;
      check(user.recording.has_value() != !user.subject.empty(),
            "a virtual user is a subject or a recording");
      check(user.recording ? user.script.empty() : !user.script.empty(),
            "a subject has a script, a recording none");
    }
  } catch (const deixis::Error& e) {
    check(std::string(e.what()).rfind("fuzz-input.json: ", 0) == 0, "errors name the file");
  }
  return 0;
}
