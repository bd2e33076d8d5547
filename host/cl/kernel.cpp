// Checked argument binding and launches; see kernel.h.
#include "host/cl/kernel.h"

#include <fmt/format.h>

#include "host/cl/launch_log.h"

namespace lorgnette::cl {

Kernel::Kernel(cl_program program, const std::string& name) : name_(name) {
  cl_int err = CL_SUCCESS;
  kernel_ = KernelHandle(clCreateKernel(program, name.c_str(), &err));
  if (err == CL_INVALID_KERNEL_NAME)
    throw Error(fmt::format("kernel '{}' is not defined in its program", name), err);
  LGN_CL_CHECK(err);
  LGN_CL_CHECK(clGetKernelInfo(kernel_.get(), CL_KERNEL_NUM_ARGS, sizeof(num_args_), &num_args_, nullptr));
}

size_t Kernel::max_work_group_size(const Runtime& rt) const {
  size_t n = 0;
  LGN_CL_CHECK(clGetKernelWorkGroupInfo(kernel_.get(), rt.device().id, CL_KERNEL_WORK_GROUP_SIZE, sizeof(n),
                                        &n, nullptr));
  return n;
}

void Kernel::set_raw(cl_uint index, size_t size, const void* value) {
  cl_int err = clSetKernelArg(kernel_.get(), index, size, value);
  if (err != CL_SUCCESS)
    throw Error(fmt::format("setting argument {} ({} bytes) of kernel '{}' failed: {}", index, size, name_,
                            error_name(err)),
                err);
}

void Kernel::check_arg_count(size_t given) const {
  if (given != num_args_)
    throw Error(fmt::format("kernel '{}' takes {} arguments but {} were bound", name_, num_args_, given),
                CL_INVALID_KERNEL_ARGS);
}

void Kernel::launch(Runtime& rt, size_t global, size_t local) { launch2d(rt, {global, 1}, {local, 1}); }

void Kernel::launch2d(Runtime& rt, std::array<size_t, 2> global, std::array<size_t, 2> local) {
  size_t max_local = max_work_group_size(rt);
  if (local[0] == 0 || local[1] == 0 || local[0] * local[1] > max_local)
    throw Error(fmt::format("kernel '{}': local size {}x{} is outside 1..{} on {}", name_, local[0], local[1],
                            max_local, rt.device().name),
                CL_INVALID_WORK_GROUP_SIZE);
  std::array<size_t, 2> g = {round_up(global[0], local[0]), round_up(global[1], local[1])};
  if (g[0] == 0 || g[1] == 0) return;  // nothing to do
  cl_uint dims = (global[1] == 1 && local[1] == 1) ? 1 : 2;
  cl_event* event = LaunchLog::active() ? LaunchLog::active()->add(name_, g, local) : nullptr;
  LGN_CL_CHECK(clEnqueueNDRangeKernel(rt.queue(), kernel_.get(), dims, nullptr, g.data(), local.data(), 0,
                                      nullptr, event));
}

}  // namespace lorgnette::cl
