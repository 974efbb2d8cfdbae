#include "tests/server/http_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

namespace brisance::testing {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

std::string ClientResponse::header(const std::string& lower_case_name) const {
  for (const auto& [name, value] : headers) {
    if (name == lower_case_name) return value;
  }
  return {};
}

struct Connection::Impl {
  asio::io_context ioc;
  beast::tcp_stream stream{ioc};
  beast::flat_buffer buffer;

  ClientResponse read(std::chrono::seconds timeout) {
    http::response_parser<http::string_body> parser;
    parser.body_limit(1ull << 30);
    stream.expires_after(timeout);
    http::read(stream, buffer, parser);
    auto& message = parser.get();
    ClientResponse out;
    out.status = static_cast<int>(message.result_int());
    for (const auto& field : message) {
      std::string name(field.name_string());
      for (char& c : name)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      out.headers.emplace_back(std::move(name), std::string(field.value()));
    }
    out.body = std::move(message.body());
    return out;
  }
};

Connection::Connection(std::uint16_t port) : impl_(std::make_unique<Impl>()) {
  impl_->stream.expires_after(std::chrono::seconds(10));
  impl_->stream.connect(tcp::endpoint(asio::ip::make_address("127.0.0.1"), port));
}

Connection::~Connection() {
  beast::error_code ignored;
  impl_->stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
}

ClientResponse Connection::request(const std::string& method, const std::string& target,
                                   const std::string& body, const Headers& headers,
                                   std::chrono::seconds timeout) {
  http::request<http::string_body> request;
  request.method_string(method);
  request.target(target);
  request.version(11);
  request.set(http::field::host, "127.0.0.1");
  bool has_type = false;
  for (const auto& [name, value] : headers) {
    request.set(name, value);
    if (beast::iequals(name, "content-type")) has_type = true;
  }
  if (!body.empty() && !has_type) request.set(http::field::content_type, "application/json");
  request.body() = body;
  request.prepare_payload();
  impl_->stream.expires_after(timeout);
  http::write(impl_->stream, request);
  return impl_->read(timeout);
}

ClientResponse Connection::raw(const std::string& bytes) {
  impl_->stream.expires_after(std::chrono::seconds(10));
  asio::write(impl_->stream, asio::buffer(bytes));
  return impl_->read(std::chrono::seconds(10));
}

bool Connection::closed_by_server() {
  impl_->stream.expires_after(std::chrono::seconds(5));
  char byte;
  beast::error_code ec;
  impl_->stream.read_some(asio::buffer(&byte, 1), ec);
  return ec == asio::error::eof || ec == asio::error::connection_reset;
}

ClientResponse http_request(std::uint16_t port, const std::string& method,
                            const std::string& target, const std::string& body,
                            const Headers& headers, std::chrono::seconds timeout) {
  Connection connection(port);
  return connection.request(method, target, body, headers, timeout);
}

}  // namespace brisance::testing
