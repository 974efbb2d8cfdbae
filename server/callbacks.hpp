// server/callbacks: telling a pipeline that its job ended. A job may name a callback URL (or the
// server give a default, --callback-url); once the job is succeeded, failed or cancelled, a
// sender POSTs the job's JSON there, signed with HMAC-SHA256 under a shared secret
// (--callback-secret), and retries with a doubling backoff until the receiver answers 2xx or the
// attempts run out. Each attempt is stored on the job (its `callback.deliveries`), and deliveries
// are claimed through the store, so any node sends each one once at a time and a restart goes on
// where it stopped. docs/service.md "Callbacks" is the receiver's side.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "server/job_service.hpp"

namespace brisance::server {

struct CallbackOptions {
  std::string secret;  // the HMAC key; empty: deliveries are sent unsigned
  std::string
      ca_file;  // PEM CAs https receivers must chain to; empty: the system's (--callback-ca)
  int max_attempts = 8;
  std::chrono::milliseconds first_backoff{2000};  // doubles after every failed attempt
  std::chrono::milliseconds max_backoff{600000};
  std::chrono::milliseconds timeout{10000};  // connect, send and receive, per attempt
  std::chrono::milliseconds poll{250};       // how often the store is asked for due deliveries
  std::chrono::milliseconds lease{120000};   // a claimed delivery is this sender's for this long
  std::size_t kept_deliveries = 20;          // attempts listed on the job (the latest)
};

// "t=UNIX_SECONDS,v1=HEX": HMAC-SHA256 under `secret` of "UNIX_SECONDS." followed by the body.
std::string callback_signature(std::string_view secret, std::int64_t unix_s, std::string_view body);

// One POST of `body` (application/json) to an http:// or https:// URL with `headers`: the status
// the receiver answered, or 0 and what went wrong (resolve, connect, timeout, TLS). https needs
// TLS 1.2 or later and a certificate that chains to `ca_file` (PEM; empty: the system's CAs) and
// names the URL's host.
struct PostOutcome {
  int status = 0;
  std::string error;
};
PostOutcome post_json(const std::string& url, const std::string& body,
                      const std::vector<std::pair<std::string, std::string>>& headers,
                      std::chrono::milliseconds timeout, const std::string& ca_file = {});

class CallbackSender {
 public:
  CallbackSender(JobService& service, CallbackOptions options);
  ~CallbackSender();
  CallbackSender(const CallbackSender&) = delete;
  CallbackSender& operator=(const CallbackSender&) = delete;

 private:
  void run();
  void deliver(const JobRecord& job);

  JobService& service_;
  CallbackOptions options_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace brisance::server
