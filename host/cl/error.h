// OpenCL error reporting: every failing call becomes a lorgnette::cl::Error that names the call,
// the error code, and the source location, so a log line is enough to find the failure.
#pragma once
#include <CL/cl.h>

#include <stdexcept>
#include <string>

namespace lorgnette::cl {

class Error : public std::runtime_error {
 public:
  Error(const std::string& what, cl_int code) : std::runtime_error(what), code_(code) {}
  cl_int code() const { return code_; }

 private:
  cl_int code_;
};

// Symbolic name of an OpenCL error code ("CL_OUT_OF_RESOURCES").
const char* error_name(cl_int code);

[[noreturn]] void throw_error(cl_int code, const char* call, const char* file, int line);

inline void check(cl_int code, const char* call, const char* file, int line) {
  if (code != CL_SUCCESS) throw_error(code, call, file, line);
}

}  // namespace lorgnette::cl

#define LGN_CL_CHECK(call) ::lorgnette::cl::check((call), #call, __FILE__, __LINE__)
