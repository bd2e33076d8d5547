// Typed, move-only device buffers: the element count travels with the handle and every transfer
// checks it, so a size mismatch is an error message rather than a silent overrun.
#pragma once
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/cl/error.h"
#include "host/cl/handles.h"
#include "host/cl/runtime.h"

namespace lorgnette::cl {

template <class T>
class Buffer {
 public:
  Buffer() = default;
  Buffer(Runtime& rt, size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE) : count_(count) {
    cl_int err = CL_SUCCESS;
    // Zero-size buffers are invalid in OpenCL; keep one element so kernels can always bind.
    size_t bytes = sizeof(T) * (count ? count : 1);
    mem_ = MemHandle(clCreateBuffer(rt.context(), flags, bytes, nullptr, &err));
    if (err == CL_INVALID_BUFFER_SIZE || err == CL_MEM_OBJECT_ALLOCATION_FAILURE ||
        err == CL_OUT_OF_RESOURCES || err == CL_OUT_OF_HOST_MEMORY)
      throw Error("Could not allocate " + std::to_string(bytes >> 20) + " MiB on " + rt.device().name +
                      ": reduce the model size or batch size",
                  err);
    LGN_CL_CHECK(err);
  }
  Buffer(Runtime& rt, const std::vector<T>& host) : Buffer(rt, host.size()) { write(rt, host); }

  size_t size() const { return count_; }
  size_t bytes() const { return count_ * sizeof(T); }
  cl_mem get() const { return mem_.get(); }

  void write(Runtime& rt, const T* data, size_t count, size_t offset = 0) {
    check_range(offset, count, "write");
    if (count == 0) return;
    LGN_CL_CHECK(clEnqueueWriteBuffer(rt.queue(), mem_.get(), CL_TRUE, offset * sizeof(T), count * sizeof(T),
                                      data, 0, nullptr, nullptr));
  }
  void write(Runtime& rt, const std::vector<T>& host, size_t offset = 0) {
    write(rt, host.data(), host.size(), offset);
  }
  void read(Runtime& rt, T* data, size_t count, size_t offset = 0) const {
    check_range(offset, count, "read");
    if (count == 0) return;
    LGN_CL_CHECK(clEnqueueReadBuffer(rt.queue(), mem_.get(), CL_TRUE, offset * sizeof(T), count * sizeof(T),
                                     data, 0, nullptr, nullptr));
  }
  std::vector<T> read(Runtime& rt, size_t count, size_t offset = 0) const {
    std::vector<T> out(count);
    read(rt, out.data(), count, offset);
    return out;
  }
  std::vector<T> read(Runtime& rt) const { return read(rt, count_); }
  void fill(Runtime& rt, const T& value, size_t offset = 0, size_t count = size_t(-1)) {
    if (count == size_t(-1)) count = count_ - offset;
    check_range(offset, count, "fill");
    if (count == 0) return;
    LGN_CL_CHECK(clEnqueueFillBuffer(rt.queue(), mem_.get(), &value, sizeof(T), offset * sizeof(T),
                                     count * sizeof(T), 0, nullptr, nullptr));
  }
  void copy_from(Runtime& rt, const Buffer<T>& src, size_t count, size_t src_off = 0, size_t dst_off = 0) {
    src.check_range(src_off, count, "copy source");
    check_range(dst_off, count, "copy destination");
    if (count == 0) return;
    LGN_CL_CHECK(clEnqueueCopyBuffer(rt.queue(), src.get(), mem_.get(), src_off * sizeof(T),
                                     dst_off * sizeof(T), count * sizeof(T), 0, nullptr, nullptr));
  }

 private:
  void check_range(size_t offset, size_t count, const char* what) const {
    if (offset + count > count_)
      throw std::out_of_range(std::string("device buffer ") + what + " of " + std::to_string(count) +
                              " elements at offset " + std::to_string(offset) + " exceeds its size " +
                              std::to_string(count_));
  }
  MemHandle mem_;
  size_t count_ = 0;
};

}  // namespace lorgnette::cl
