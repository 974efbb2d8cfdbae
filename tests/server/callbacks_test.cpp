// Callbacks end to end: a job names a URL, a local receiver answers it, and the deliveries, their
// signature, their retries and their record on the job are checked. A real server, a real HTTP
// receiver on the loopback, a real store.
#include <cstdio>
#include <cstring>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>

#include "tests/server/test_server.hpp"
#include "tests/server/test_tls.hpp"

namespace brisance::testing {
namespace {

using nlohmann::json;
namespace beast = boost::beast;
namespace http = boost::beast::http;
using tcp = boost::asio::ip::tcp;

namespace ssl = boost::asio::ssl;

// An HTTP receiver on 127.0.0.1 that answers each request with the next of `statuses` (then
// 200) and keeps what it got; over TLS with the test CA's localhost certificate when `tls`.
class Receiver {
 public:
  struct Request {
    std::string target;
    std::string body;
    std::string signature;
    std::string event;
    std::string delivery;
  };

  explicit Receiver(std::deque<int> statuses, bool tls = false)
      : statuses_(std::move(statuses)), tls_(tls), acceptor_(io_, tcp::endpoint(tcp::v4(), 0)) {
    if (tls_) {
      tls_context_.use_certificate_chain(
          boost::asio::buffer(kLocalhostCertificate, std::strlen(kLocalhostCertificate)));
      tls_context_.use_private_key(boost::asio::buffer(kLocalhostKey, std::strlen(kLocalhostKey)),
                                   ssl::context::pem);
    }
    thread_ = std::thread([this] { serve(); });
  }
  ~Receiver() {
    stopping_ = true;
    beast::error_code ignored;
    // Wake the blocking accept with one last connection.
    tcp::socket poke(io_);
    poke.connect(acceptor_.local_endpoint(), ignored);
    thread_.join();
  }
  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }
  std::vector<Request> requests() {
    std::lock_guard lock(mutex_);
    return requests_;
  }

 private:
  void serve() {
    while (!stopping_) {
      tcp::socket socket(io_);
      beast::error_code ec;
      acceptor_.accept(socket, ec);
      if (ec || stopping_) continue;
      if (!tls_) {
        answer(socket);
        continue;
      }
      ssl::stream<tcp::socket> stream(std::move(socket), tls_context_);
      stream.handshake(ssl::stream_base::server, ec);
      if (ec) {
        std::lock_guard lock(mutex_);
        ++refused_handshakes_;
        continue;
      }
      answer(stream);
      stream.shutdown(ec);
    }
  }

  template <class Stream>
  void answer(Stream& socket) {
    {
      beast::error_code ec;
      beast::flat_buffer buffer;
      http::request<http::string_body> request;
      http::read(socket, buffer, request, ec);
      if (ec) return;
      int status = 200;
      {
        std::lock_guard lock(mutex_);
        requests_.push_back({std::string(request.target()), request.body(),
                             std::string(request["Brisance-Signature"]),
                             std::string(request["Brisance-Event"]),
                             std::string(request["Brisance-Delivery"])});
        if (!statuses_.empty()) {
          status = statuses_.front();
          statuses_.pop_front();
        }
      }
      http::response<http::string_body> response{static_cast<http::status>(status), 11};
      response.body() = "ok";
      response.prepare_payload();
      http::write(socket, response, ec);
    }
  }

 public:
  int refused_handshakes() {
    std::lock_guard lock(mutex_);
    return refused_handshakes_;
  }

 private:
  std::deque<int> statuses_;
  bool tls_ = false;
  ssl::context tls_context_{ssl::context::tls_server};
  int refused_handshakes_ = 0;
  boost::asio::io_context io_;
  tcp::acceptor acceptor_;
  std::mutex mutex_;
  std::vector<Request> requests_;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

TestServerOptions with_callbacks(int max_attempts) {
  TestServerOptions options;
  server::CallbackOptions callbacks;
  callbacks.secret = "s3cret";
  callbacks.max_attempts = max_attempts;
  callbacks.first_backoff = std::chrono::milliseconds(100);
  callbacks.poll = std::chrono::milliseconds(20);
  callbacks.timeout = std::chrono::milliseconds(2000);
  options.callbacks = callbacks;
  return options;
}

// Polls the job until its callback is in `state` (a finished job's long-poll does not wait),
// for up to 20 s.
json wait_for_callback(TestServer& server, const std::string& id, std::string_view state) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  json job = server.get_json("/v1/jobs/" + id);
  while (!(job.at("callback").is_object() && job.at("callback").at("state") == state) &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    job = server.get_json("/v1/jobs/" + id);
  }
  return job;
}

std::string submit_with_callback(TestServer& server, const std::string& url) {
  const json body = {{"scene", quick_scene()}, {"callback", url}};
  const ClientResponse r = server.request("POST", "/v1/jobs", body.dump());
  EXPECT_EQ(r.status, 202) << r.body;
  const json job = json::parse(r.body);
  EXPECT_EQ(job.at("callback").at("url"), url);
  EXPECT_EQ(job.at("callback").at("state"), "pending");
  return job.at("id");
}

// HMAC-SHA256 straight from libcrypto, as a receiver computes it.
std::string hmac_hex(const std::string& key, const std::string& message) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()),
       reinterpret_cast<const unsigned char*>(message.data()), message.size(), digest, &length);
  std::string hex;
  char pair[3];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(pair, sizeof pair, "%02x", digest[i]);
    hex += pair;
  }
  return hex;
}

TEST(Callbacks, AFinishedJobIsPostedSignedAndRetriedUntilTheReceiverTakesIt) {
  Receiver receiver({500});
  TestServer server(with_callbacks(5));
  const std::string url =
      "http://127.0.0.1:" + std::to_string(receiver.port()) + "/hooks/done?shot=7";
  const std::string id = submit_with_callback(server, url);
  const json job = wait_for_callback(server, id, "delivered");
  ASSERT_EQ(job.at("callback").at("state"), "delivered") << job.dump();
  EXPECT_EQ(job.at("status"), "succeeded");

  const std::vector<Receiver::Request> got = receiver.requests();
  ASSERT_EQ(got.size(), 2u);  // refused once (500), taken the second time
  for (std::size_t i = 0; i < got.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(got[i].target, "/hooks/done?shot=7");
    EXPECT_EQ(got[i].event, "job.finished");
    EXPECT_EQ(got[i].delivery, id + "." + std::to_string(i + 1));
    const json sent = json::parse(got[i].body);
    EXPECT_EQ(sent.at("id"), id);
    EXPECT_EQ(sent.at("status"), "succeeded");
    // t=SECONDS,v1=HMAC-SHA256(secret, "SECONDS." + body)
    const std::string& signature = got[i].signature;
    ASSERT_EQ(signature.rfind("t=", 0), 0u) << signature;
    const std::size_t comma = signature.find(",v1=");
    ASSERT_NE(comma, std::string::npos) << signature;
    const std::string stamp = signature.substr(2, comma - 2);
    EXPECT_EQ(signature.substr(comma + 4), hmac_hex("s3cret", stamp + "." + got[i].body));
    EXPECT_NE(signature.substr(comma + 4), hmac_hex("other", stamp + "." + got[i].body));
  }
  const json& deliveries = job.at("callback").at("deliveries");
  ASSERT_EQ(deliveries.size(), 2u);
  EXPECT_EQ(deliveries[0].at("status"), 500);
  EXPECT_EQ(deliveries[0].at("attempt"), 1);
  EXPECT_EQ(deliveries[1].at("status"), 200);
  EXPECT_TRUE(deliveries[1].at("error").is_null());
}

TEST(Callbacks, AnUnreachableReceiverFailsAfterTheLastAttempt) {
  // A port nothing listens on: the receiver is gone before the job ends.
  std::uint16_t port = 0;
  { port = Receiver({}).port(); }
  TestServer server(with_callbacks(2));
  const std::string id =
      submit_with_callback(server, "http://127.0.0.1:" + std::to_string(port) + "/");
  const json job = wait_for_callback(server, id, "failed");
  ASSERT_EQ(job.at("callback").at("state"), "failed") << job.dump();
  const json& deliveries = job.at("callback").at("deliveries");
  ASSERT_EQ(deliveries.size(), 2u);
  for (const json& delivery : deliveries) {
    EXPECT_TRUE(delivery.at("status").is_null());
    EXPECT_FALSE(delivery.at("error").get<std::string>().empty());
  }
}

TEST(Callbacks, TheServersDefaultURLAndBadURLs) {
  Receiver receiver({});
  TestServerOptions options = with_callbacks(3);
  options.default_callback_url = "http://127.0.0.1:" + std::to_string(receiver.port()) + "/all";
  TestServer server(options);
  const ClientResponse r = server.request("POST", "/v1/jobs", job_body(quick_scene()));
  ASSERT_EQ(r.status, 202);
  const std::string id = json::parse(r.body).at("id");
  EXPECT_EQ(wait_for_callback(server, id, "delivered").at("callback").at("state"), "delivered");
  ASSERT_EQ(receiver.requests().size(), 1u);
  EXPECT_EQ(receiver.requests()[0].target, "/all");

  for (const std::string bad : {"ftp://example.com/", "not a url", "http://user:pw@example.com/"}) {
    const ClientResponse refused = server.request(
        "POST", "/v1/jobs", json{{"scene", quick_scene()}, {"callback", bad}}.dump());
    EXPECT_EQ(refused.status, 422) << bad;
    EXPECT_NE(refused.body.find("/callback"), std::string::npos) << refused.body;
  }
}

// One job's callback to a TLS receiver at https://HOST:PORT/tls, with `ca_file` trusted (empty:
// the system's CAs only), until the callback is `state`; the job as then shown.
json https_callback(Receiver& receiver, const std::string& host, const std::string& ca_file,
                    int max_attempts, std::string_view state) {
  TestServerOptions options = with_callbacks(max_attempts);
  options.callbacks->ca_file = ca_file;
  TestServer server(options);
  const std::string url = "https://" + host + ":" + std::to_string(receiver.port()) + "/tls";
  const json job = wait_for_callback(server, submit_with_callback(server, url), state);
  EXPECT_EQ(job.at("callback").at("state"), state) << job.dump();
  return job;
}

// https: the receiver's certificate must chain to a trusted CA and name the host. Trusting the
// test CA (--callback-ca) the delivery goes through, signed as over http; with the system's CAs
// alone the handshake is refused, the attempt fails with the reason, and nothing is delivered.
TEST(Callbacks, HttpsDeliversToATrustedCertificateAndRefusesAnUntrustedOne) {
  const std::string ca_file = ::testing::TempDir() + "brisance-test-ca.pem";
  std::ofstream(ca_file) << kTestCa;
  {
    Receiver receiver({}, true);
    const json job = https_callback(receiver, "127.0.0.1", ca_file, 2, "delivered");
    ASSERT_EQ(receiver.requests().size(), 1u);
    EXPECT_EQ(receiver.requests()[0].target, "/tls");
    EXPECT_EQ(receiver.requests()[0].event, "job.finished");
    EXPECT_EQ(json::parse(receiver.requests()[0].body).at("id"), job.at("id"));
    EXPECT_EQ(receiver.refused_handshakes(), 0);
  }
  {
    // The system's CAs, which do not include the test CA.
    Receiver receiver({}, true);
    const json job = https_callback(receiver, "127.0.0.1", "", 2, "failed");
    EXPECT_TRUE(receiver.requests().empty());
    EXPECT_EQ(receiver.refused_handshakes(), 2);
    const json& deliveries = job.at("callback").at("deliveries");
    ASSERT_EQ(deliveries.size(), 2u);
    const std::string error = deliveries[0].at("error");
    EXPECT_NE(error.find("certificate verify failed"), std::string::npos) << error;
  }
  {
    // Trusted CA, wrong name: the certificate is for localhost and 127.0.0.1, not 127.0.0.2.
    Receiver receiver({}, true);
    https_callback(receiver, "127.0.0.2", ca_file, 1, "failed");
    EXPECT_TRUE(receiver.requests().empty());
  }
  std::remove(ca_file.c_str());
}

}  // namespace
}  // namespace brisance::testing
