// A small blocking HTTP/1.1 client over Boost.Beast for the server tests: one request per
// connection, the status and body back, or status 0 when the server closed without answering.
// Built once (http_client.cpp, library lgn_test_http_client): Beast's headers stay out of the tests.
#pragma once
#include <cstdint>
#include <string>

namespace lorgnette::service::test {

struct HttpReply {
  int status = 0;
  std::string body, content_type;
};

HttpReply http_request(uint16_t port, const std::string& method, const std::string& target,
                       const std::string& token = "", const std::string& body = "");

}  // namespace lorgnette::service::test
