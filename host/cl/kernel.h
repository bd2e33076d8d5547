// A kernel with checked argument binding and checked launches: all arguments are bound at once in
// order (the count is checked against the kernel's signature), and a launch verifies the global
// size is a multiple of the explicit local size and that the local size fits the device, naming
// both numbers when it does not. PoCL needs an explicit local size (NULL picked 4096 and
// overflowed the stack), so there is no launch without one.
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <type_traits>

#include "host/cl/buffer.h"
#include "host/cl/error.h"
#include "host/cl/handles.h"
#include "host/cl/runtime.h"

namespace lorgnette::cl {

// Marks a __local scratch argument of `bytes` bytes.
struct LocalBytes {
  size_t bytes;
};

class Kernel {
 public:
  Kernel() = default;
  Kernel(cl_program program, const std::string& name);

  const std::string& name() const { return name_; }
  cl_kernel get() const { return kernel_.get(); }
  size_t max_work_group_size(const Runtime& rt) const;

  template <class... Args>
  Kernel& args(const Args&... a) {
    check_arg_count(sizeof...(Args));
    cl_uint i = 0;
    (set_one(i++, a), ...);
    return *this;
  }

  // 1D launch; global is rounded up to a multiple of local (kernels bound-check with a count).
  void launch(Runtime& rt, size_t global, size_t local);
  void launch2d(Runtime& rt, std::array<size_t, 2> global, std::array<size_t, 2> local);

 private:
  template <class T>
  void set_one(cl_uint i, const Buffer<T>& b) {
    cl_mem m = b.get();
    set_raw(i, sizeof(cl_mem), &m);
  }
  void set_one(cl_uint i, const LocalBytes& l) { set_raw(i, l.bytes, nullptr); }
  template <class T>
  void set_one(cl_uint i, const T& v) {
    static_assert(std::is_trivially_copyable_v<T>, "kernel arguments must be plain data");
    static_assert(!std::is_same_v<T, bool> && !std::is_same_v<T, size_t>,
                  "bool and size_t have no portable OpenCL equivalent: use int32_t / uint32_t");
    set_raw(i, sizeof(T), &v);
  }
  void set_raw(cl_uint index, size_t size, const void* value);
  void check_arg_count(size_t given) const;

  KernelHandle kernel_;
  std::string name_;
  cl_uint num_args_ = 0;
};

inline size_t round_up(size_t n, size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

}  // namespace lorgnette::cl
