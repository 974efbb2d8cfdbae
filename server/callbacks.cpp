#include "server/callbacks.hpp"

#include <algorithm>
#include <cstdio>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/address.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/url/parse.hpp>
#include <nlohmann/json.hpp>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include "server/log.hpp"
#include "server/routes/routes.hpp"

namespace brisance::server {

namespace beast = boost::beast;
namespace http = boost::beast::http;
using tcp = boost::asio::ip::tcp;
using nlohmann::json;

std::string callback_signature(std::string_view secret, std::int64_t unix_s,
                               std::string_view body) {
  const std::string stamp = std::to_string(unix_s);
  std::string message = stamp + ".";
  message.append(body);
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (!HMAC(EVP_sha256(), secret.data(), static_cast<int>(secret.size()),
            reinterpret_cast<const unsigned char*>(message.data()), message.size(), digest,
            &length))
    throw std::runtime_error("libcrypto could not compute an HMAC-SHA256");
  std::string hex = "t=" + stamp + ",v1=";
  char pair[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(pair, sizeof pair, "%02x", digest[i]);
    hex += pair;
  }
  return hex;
}

namespace {

// The request and its answer over an open stream (TCP or TLS): the status the receiver answered.
template <class Stream>
int exchange(Stream& stream, beast::tcp_stream& timer, http::request<http::string_body>& request,
             std::chrono::milliseconds timeout) {
  timer.expires_after(timeout);
  http::write(stream, request);
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(64 * 1024);  // the answer is not used; a receiver must not flood us
  timer.expires_after(timeout);
  http::read(stream, buffer, parser);
  return static_cast<int>(parser.get().result_int());
}

// "certificate verify failed (self-signed certificate in certificate chain)" rather than the
// bare "certificate verify failed" OpenSSL's error string gives.
std::string tls_error(const boost::system::system_error& e, SSL* ssl) {
  std::string message = e.what();
  const long verify = ssl != nullptr ? SSL_get_verify_result(ssl) : X509_V_OK;
  if (verify != X509_V_OK) {
    message += " (";
    message += X509_verify_cert_error_string(verify);
    message += ")";
  }
  return message;
}

}  // namespace

PostOutcome post_json(const std::string& url, const std::string& body,
                      const std::vector<std::pair<std::string, std::string>>& headers,
                      std::chrono::milliseconds timeout, const std::string& ca_file) {
  PostOutcome outcome;
  const auto parsed = boost::urls::parse_absolute_uri(url);
  const bool tls = parsed && parsed->scheme() == "https";
  if (!parsed || (parsed->scheme() != "http" && !tls)) {
    outcome.error = "not an http:// or https:// URL";
    return outcome;
  }
  const std::string host = parsed->host();
  const std::string port =
      parsed->has_port() ? std::string(parsed->port()) : std::string(tls ? "443" : "80");
  std::string target = parsed->encoded_path().empty() ? "/" : std::string(parsed->encoded_path());
  if (parsed->has_query()) target += "?" + std::string(parsed->encoded_query());
  SSL* ssl_handle = nullptr;
  try {
    boost::asio::io_context io;
    tcp::resolver resolver(io);
    http::request<http::string_body> request{http::verb::post, target, 11};
    request.set(http::field::host, parsed->encoded_host_and_port());
    request.set(http::field::user_agent, "brisance-callbacks");
    request.set(http::field::content_type, "application/json");
    for (const auto& [name, value] : headers)
      request.set(name, value);
    request.body() = body;
    request.prepare_payload();
    if (!tls) {
      beast::tcp_stream stream(io);
      stream.expires_after(timeout);
      stream.connect(resolver.resolve(host, port));
      outcome.status = exchange(stream, stream, request, timeout);
      beast::error_code ignored;
      stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
      return outcome;
    }
    // TLS 1.2 or later; the receiver's certificate must chain to the system's trusted CAs (or
    // to --callback-ca) and name the URL's host.
    namespace ssl = boost::asio::ssl;
    ssl::context context(ssl::context::tls_client);
    context.set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                        ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1);
    if (ca_file.empty()) {
      context.set_default_verify_paths();
    } else {
      context.load_verify_file(ca_file);
    }
    context.set_verify_mode(ssl::verify_peer);
    beast::ssl_stream<beast::tcp_stream> stream(io, context);
    ssl_handle = stream.native_handle();
    boost::system::error_code not_an_address;
    boost::asio::ip::make_address(host, not_an_address);
    // SSL_set_tlsext_host_name without its macro's C cast.
    if (not_an_address && SSL_ctrl(ssl_handle, SSL_CTRL_SET_TLSEXT_HOSTNAME,
                                   TLSEXT_NAMETYPE_host_name, const_cast<char*>(host.c_str())) != 1)
      throw std::runtime_error("cannot set the TLS server name (SNI) to " + host);
    stream.set_verify_callback(ssl::host_name_verification(host));
    beast::get_lowest_layer(stream).expires_after(timeout);
    beast::get_lowest_layer(stream).connect(resolver.resolve(host, port));
    stream.handshake(ssl::stream_base::client);
    outcome.status = exchange(stream, beast::get_lowest_layer(stream), request, timeout);
    beast::error_code ignored;
    beast::get_lowest_layer(stream).expires_after(timeout);
    stream.shutdown(ignored);  // receivers often close without a close_notify: not an error
  } catch (const boost::system::system_error& e) {
    outcome.status = 0;
    outcome.error = tls ? tls_error(e, ssl_handle) : e.what();
  } catch (const std::exception& e) {
    outcome.status = 0;
    outcome.error = e.what();
  }
  return outcome;
}

CallbackSender::CallbackSender(JobService& service, CallbackOptions options)
    : service_(service), options_(std::move(options)), thread_([this] { run(); }) {}

CallbackSender::~CallbackSender() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void CallbackSender::run() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    lock.unlock();
    bool sent = false;
    try {
      if (auto job = service_.claim_callback(options_.lease.count())) {
        deliver(*job);
        sent = true;
      }
    } catch (const std::exception& e) {
      log_event(LogLevel::warn, "callback", {{"error", e.what()}});
    }
    lock.lock();
    // Due deliveries go one after another; otherwise ask again after the poll interval.
    if (!sent) wake_.wait_for(lock, options_.poll, [this] { return stopping_; });
  }
}

void CallbackSender::deliver(const JobRecord& job) {
  json deliveries = json::parse(job.callback_deliveries_json, nullptr, false);
  if (!deliveries.is_array()) deliveries = json::array();
  const int attempt =
      deliveries.empty()
          ? 1
          : deliveries.back().value("attempt", static_cast<int>(deliveries.size())) + 1;
  const std::string body = routes::job_json(job);
  const std::int64_t sent_ms = now_ms();
  std::vector<std::pair<std::string, std::string>> headers = {
      {"Brisance-Event", "job.finished"},
      {"Brisance-Delivery", job.id + "." + std::to_string(attempt)}};
  if (!options_.secret.empty())
    headers.emplace_back("Brisance-Signature",
                         callback_signature(options_.secret, sent_ms / 1000, body));
  const PostOutcome outcome =
      post_json(job.callback_url, body, headers, options_.timeout, options_.ca_file);
  const bool delivered = outcome.status >= 200 && outcome.status < 300;
  json entry = {{"attempt", attempt},
                {"at", iso_time_utc(sent_ms)},
                {"status", outcome.status > 0 ? json(outcome.status) : json(nullptr)},
                {"error", outcome.error.empty() ? json(nullptr) : json(outcome.error)}};
  deliveries.push_back(std::move(entry));
  while (deliveries.size() > options_.kept_deliveries)
    deliveries.erase(deliveries.begin());
  std::string state = delivered ? "delivered" : "pending";
  std::int64_t next_ms = 0;
  if (!delivered) {
    if (attempt >= options_.max_attempts) {
      state = "failed";
    } else {
      const auto backoff =
          std::min(options_.max_backoff, options_.first_backoff * (1 << std::min(attempt - 1, 20)));
      next_ms = now_ms() + backoff.count();
    }
  }
  log_event(LogLevel::info, "callback",
            {{"job", job.id},
             {"attempt", attempt},
             {"status", outcome.status},
             {"state", state},
             {"error", outcome.error}});
  service_.record_callback(job.id, deliveries.dump(), state, next_ms);
}

}  // namespace brisance::server
