// Move-only RAII owners for OpenCL handles: a handle is released exactly once, destructors never
// throw (a failing release is logged), and copies cannot happen by accident.
#pragma once
#include <CL/cl.h>

#include <typeinfo>
#include <utility>

namespace lorgnette::cl {

void log_release_failure(const char* what, cl_int code);

template <class T, cl_int (*Release)(T), cl_int (*Retain)(T)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(T h) : h_(h) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  // A new owner of the same object (clRetain*), for sharing across classes explicitly.
  Handle share() const {
    if (h_) Retain(h_);
    return Handle(h_);
  }
  void reset() {
    if (h_) {
      cl_int code = Release(h_);
      if (code != CL_SUCCESS) log_release_failure(typeid(T).name(), code);
      h_ = nullptr;
    }
  }
  T get() const { return h_; }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  T h_ = nullptr;
};

using ContextHandle = Handle<cl_context, clReleaseContext, clRetainContext>;
using QueueHandle = Handle<cl_command_queue, clReleaseCommandQueue, clRetainCommandQueue>;
using ProgramHandle = Handle<cl_program, clReleaseProgram, clRetainProgram>;
using KernelHandle = Handle<cl_kernel, clReleaseKernel, clRetainKernel>;
using MemHandle = Handle<cl_mem, clReleaseMemObject, clRetainMemObject>;
using EventHandle = Handle<cl_event, clReleaseEvent, clRetainEvent>;

}  // namespace lorgnette::cl
