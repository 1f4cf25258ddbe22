#pragma once
// A site's network side (docs/protocol.md): the ENet link and the session, hosting or joining,
// with the site's hello (its user's body calibration and avatar) and target map. Waiting for the
// peer turns every way a connection can fail into an error that says what happened (refused and
// why, nobody came, time-outs).

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "net/enet_link.h"
#include "net/session.h"
#include "site/site_config.h"

namespace deixis::site {

// Seconds since construction, on the steady clock: the one clock a site runs on.
class SiteClock {
 public:
  double now() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

struct SiteSessionOptions {
  net::Role role = net::Role::kHost;
  std::string address = "127.0.0.1";  // host: the address to bind; joiner: the host's
  std::uint16_t port = 0;             // host: 0 picks a free port (see port())
  std::string passphrase;
  // The avatar file the user chose, offered by its hash in the hello (net::SessionConfig).
  std::shared_ptr<const std::vector<std::byte>> avatar_file{};
};

// A site's hello: its name and its user's body calibration; the avatar they wear is the
// receiving site's choice (an empty avatar model).
net::Hello site_hello(const SiteConfig& site, const BodyCalibration& user);

class SiteSession {
 public:
  // Throws deixis::Error when the port cannot be bound, the address does not resolve, the hello
  // or target map break a wire rule, or a host would listen beyond loopback without a passphrase
  // and open sessions were not allowed (site/endpoint.h, host_exposure_problem).
  SiteSession(const SiteSessionOptions& options, net::Hello hello, TargetMap map);
  ~SiteSession();
  SiteSession(const SiteSession&) = delete;
  SiteSession& operator=(const SiteSession&) = delete;

  std::uint16_t port() const { return link_->port(); }

  // Starts the session; then poll() every tick until streaming(). poll() services the link
  // without waiting (a loop that must keep running, an OpenXR frame loop) and throws
  // deixis::Error naming the cause when the peer refuses us (or we it, for a joiner), or when
  // nobody streams within `timeout` s of start().
  void start(double now, double timeout);
  void poll(double now);
  bool streaming() const;

  net::Session& session() { return *session_; }
  const net::Session& session() const { return *session_; }
  const net::EnetLink& link() const { return *link_; }

  // Says bye and lets ENet deliver it (at most 0.5 s), so the peer does not wait for a time-out.
  void close(double now);

 private:
  [[noreturn]] void fail_to_connect(double timeout) const;

  SiteSessionOptions options_;
  double deadline_ = 0.0;  // of start(), until the first stream
  double timeout_ = 0.0;
  std::unique_ptr<net::EnetLink> link_;
  std::unique_ptr<net::Session> session_;
  bool closed_ = false;
};

}  // namespace deixis::site
