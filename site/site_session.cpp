#include "site/site_session.h"

#include <string>
#include <utility>

#include "core/error.h"
#include "site/endpoint.h"

namespace deixis::site {

namespace {

std::string refusal_message(const net::PeerStatus& status, net::Role role) {
  const std::string reason(net::bye_reason_name(status.last_bye));
  std::string who = role == net::Role::kJoiner ? "the host refused this site" : "refused";
  std::string hint;
  if (status.last_bye == net::ByeReason::kWeakKeyCost) {
    // The joiner refused the host (docs/security.md, "Threat model").
    who = "this site refused the host";
    hint =
        " (below libsodium's INTERACTIVE cost a host could test passphrase guesses against "
        "this site's proof cheaply: is it the host you meant?)";
  }
  if (status.last_bye == net::ByeReason::kAuthenticationFailed) {
    hint = " (the passphrases differ)";
  } else if (status.last_bye == net::ByeReason::kPassphraseRequired) {
    hint = " (the host needs a passphrase: " + std::string(kPassphraseVariable) +
           ", --passphrase-file or --ask-passphrase)";
  } else if (status.last_bye == net::ByeReason::kPassphraseUnexpected) {
    hint = " (the host has no passphrase; leave it out, and unset " +
           std::string(kPassphraseVariable) + ")";
  }
  return who + ": " + reason + hint;
}

}  // namespace

net::Hello site_hello(const SiteConfig& site, const BodyCalibration& user) {
  net::Hello h;
  h.site = site.site;
  h.avatar.model = "";
  h.avatar.body = user;
  return h;
}

SiteSession::SiteSession(const SiteSessionOptions& options, net::Hello hello, TargetMap map)
    : options_(options) {
  if (options.role == net::Role::kHost) {
    // Below every command line and the simulator's panel: no host goes beyond loopback
    // unprotected unless the person asked for it (--open).
    const std::string problem = host_exposure_problem(options.address, !options.passphrase.empty());
    if (!problem.empty()) {
      throw Error(problem);
    }
  }
  link_ = options.role == net::Role::kHost ? net::EnetLink::host(options.address, options.port)
                                           : net::EnetLink::join(options.address, options.port);
  net::SessionConfig config;
  config.role = options.role;
  config.hello = std::move(hello);
  config.target_map = std::move(map);
  config.passphrase = options.passphrase;
  config.avatar_file = options.avatar_file;
  link_->set_timeout_ms(static_cast<std::uint32_t>(config.heartbeat_timeout * 1000.0) + 2000);
  session_ = std::make_unique<net::Session>(*link_, std::move(config));
}

SiteSession::~SiteSession() {
  if (!closed_) {
    session_->close(0.0);
    link_->drain(200);
  }
}

void SiteSession::start(double now, double timeout) {
  deadline_ = now + timeout;
  timeout_ = timeout;
  session_->start(now);
}

bool SiteSession::streaming() const {
  return session_->state() == net::SessionState::kStreaming;
}

void SiteSession::poll(double now) {
  session_->service(now, 0);
  if (session_->state() == net::SessionState::kRefused) {
    throw Error(refusal_message(session_->status(), options_.role));
  }
  if (session_->status().streams == 0 && !streaming() && now > deadline_) {
    fail_to_connect(timeout_);
  }
}

void SiteSession::fail_to_connect(double timeout) const {
  std::string what = options_.role == net::Role::kHost
                         ? "no site joined within " + std::to_string(timeout) + " s"
                         : "could not reach the host " + options_.address + ":" +
                               std::to_string(options_.port) + " within " +
                               std::to_string(timeout) + " s";
  const net::PeerStatus& status = session_->status();
  if (status.auth_failures > 0) {
    what += " (" + std::to_string(status.auth_failures) + " joiner(s) refused: wrong passphrase)";
  } else if (status.last_end != net::EndCause::kNone) {
    what += " (last attempt: " + std::string(net::end_cause_name(status.last_end)) + ")";
  }
  throw Error(what);
}

void SiteSession::close(double now) {
  if (!closed_) {
    session_->close(now);
    link_->drain(500);
    closed_ = true;
  }
}

}  // namespace deixis::site
