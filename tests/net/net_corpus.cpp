// net_corpus DIR: writes the seed corpora of the net fuzz targets into DIR/net_packet/ and
// DIR/net_session/ (fuzz/corpus/ in the repository): one valid packet of every message type and a
// few malformed ones, and session scripts that inject them during the handshake and while
// streaming. Rerun after a protocol change:  build/<preset>/tests/net_corpus fuzz/corpus

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "net/avatar_transfer.h"
#include "net/messages.h"
#include "net/tracking_codec.h"
#include "net_fixtures.h"

namespace {

using namespace deixis;
using namespace deixis::net;
using Bytes = std::vector<std::byte>;
namespace fs = std::filesystem;

void write(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

Bytes tracking(std::uint8_t valid) {
  const Vec3 root(0.25f, 1.6f, -3.0f);  // the root the fuzz target decodes with
  TrackingMessage m{42, testing::moving_frame(42, root)};
  m.frame.valid = valid;
  Bytes b(kTrackingBytes);
  encode_tracking(m, root, b);
  return b;
}

// A session script record: [flags][length][bytes].
void record(Bytes& script, bool tracking_channel, bool to_host, const Bytes& packet) {
  script.push_back(
      std::byte{static_cast<unsigned char>((tracking_channel ? 1 : 0) | (to_host ? 2 : 0))});
  script.push_back(
      std::byte{static_cast<unsigned char>(std::min<std::size_t>(packet.size(), 255))});
  script.insert(
      script.end(), packet.begin(),
      packet.begin() + static_cast<std::ptrdiff_t>(std::min<std::size_t>(packet.size(), 255)));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const fs::path packets = fs::path(argv[1]) / "net_packet";
  const fs::path sessions = fs::path(argv[1]) / "net_session";
  fs::create_directories(packets);
  fs::create_directories(sessions);

  Welcome welcome;
  Bytes welcome_open, welcome_secret, join, accept, hello, map, map_empty;
  encode(welcome, welcome_open);
  welcome.auth = AuthMode::kPassphrase;
  welcome.kdf = {2, 65536};
  welcome.salt.fill(std::byte{7});
  encode(welcome, welcome_secret);
  encode(Join{}, join);
  encode(Accept{}, accept);
  encode(testing::make_hello("Site A"), hello);
  encode(testing::make_target_map("B", 3), map);
  encode(testing::make_target_map("", 0), map_empty);
  Bytes heartbeat(kHeartbeatBytes), bye(kByeBytes);
  encode(Heartbeat{7}, heartbeat);
  encode(Bye{ByeReason::kAuthenticationFailed}, bye);
  const Bytes full = tracking(tracked::kAll);
  Bytes truncated = full;
  truncated.pop_back();
  Bytes nan_hello = hello;
  nan_hello[13] = std::byte{0x00}, nan_hello[14] = std::byte{0x00};
  nan_hello[15] = std::byte{0xC0}, nan_hello[16] = std::byte{0x7F};  // height: NaN
  const Bytes avatar_file(300, std::byte{0x5A});
  Bytes avatar_request(kAvatarRequestBytes);
  encode(AvatarRequest{avatar_hash(avatar_file)}, avatar_request);
  Bytes avatar_data(kAvatarDataHeaderBytes + 200);
  encode(AvatarData{avatar_hash(avatar_file), 300, 100, std::span(avatar_file).subspan(100)},
         avatar_data);
  Bytes sealed(40, std::byte{0x33});
  sealed[0] = std::byte{0x20};

  const std::vector<std::pair<std::string, Bytes>> seeds = {
      {"welcome-open", welcome_open},
      {"welcome-passphrase", welcome_secret},
      {"join", join},
      {"accept", accept},
      {"hello", hello},
      {"target-map", map},
      {"target-map-empty", map_empty},
      {"heartbeat", heartbeat},
      {"bye", bye},
      {"tracking-all-parts", full},
      {"tracking-head-only", tracking(tracked::kHead)},
      {"tracking-nothing-valid", tracking(0)},
      {"bad-tracking-truncated", truncated},
      {"bad-hello-nan-height", nan_hello},
      {"sealed-garbage", sealed},
      {"avatar-request", avatar_request},
      {"avatar-data", avatar_data},
      {"empty", {}}};
  for (const auto& [name, bytes] : seeds) {
    write(packets / (name + ".bin"), bytes);
  }

  // Sessions: open or sealed, during the handshake or while streaming.
  for (const int mode : {0, 1, 2, 3}) {
    Bytes script = {static_cast<std::byte>(mode)};
    record(script, true, false, full);
    record(script, false, false, hello);
    record(script, false, true, map);
    record(script, false, false, welcome_open);
    record(script, false, true, join);
    record(script, true, true, sealed);
    record(script, false, false, heartbeat);
    record(script, false, true, truncated);
    write(sessions / ("mixed-mode" + std::to_string(mode) + ".bin"), script);
  }
  Bytes bye_script = {std::byte{2}};
  record(bye_script, false, false, bye);
  write(sessions / "streaming-bye-to-joiner.bin", bye_script);
  std::printf("wrote %zu packet seeds and 5 session seeds under %s\n", seeds.size(), argv[1]);
  return 0;
}
