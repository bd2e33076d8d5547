// An API failure as an HTTP status, a stable machine-readable code and a message for a person
// (what is wrong and what to do); Api::handle turns it into {"error": {"code", "message"}}.
#pragma once
#include <stdexcept>
#include <string>

namespace lorgnette::service {

struct ApiError : std::runtime_error {
  ApiError(int status, std::string code, const std::string& message)
      : std::runtime_error(message), status(status), code(std::move(code)) {}
  int status;
  std::string code;
};

}  // namespace lorgnette::service
