// tests/server/http_client: a real HTTP/1.1 client (Boost.Beast, synchronous) for the server
// tests. One request per connection unless a Connection is kept.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace brisance::testing {

struct ClientResponse {
  int status = 0;
  std::vector<std::pair<std::string, std::string>> headers;  // names lower-case
  std::string body;
  std::string header(const std::string& lower_case_name) const;
};

using Headers = std::vector<std::pair<std::string, std::string>>;

// A keep-alive connection to 127.0.0.1:port.
class Connection {
 public:
  explicit Connection(std::uint16_t port);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ClientResponse request(const std::string& method, const std::string& target,
                         const std::string& body = {}, const Headers& headers = {},
                         std::chrono::seconds timeout = std::chrono::seconds(60));
  // Sends raw bytes and reads one response (for malformed-request tests).
  ClientResponse raw(const std::string& bytes);
  bool closed_by_server();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

ClientResponse http_request(std::uint16_t port, const std::string& method,
                            const std::string& target, const std::string& body = {},
                            const Headers& headers = {},
                            std::chrono::seconds timeout = std::chrono::seconds(60));

}  // namespace brisance::testing
