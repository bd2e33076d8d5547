// LaunchLog: see launch_log.h.
#include "host/cl/launch_log.h"

#include <stdexcept>

#include "host/cl/error.h"

namespace lorgnette::cl {
namespace {
LaunchLog* g_active = nullptr;
}

LaunchLog::LaunchLog() {
  if (g_active) throw std::logic_error("LaunchLog: another log is already recording");
  g_active = this;
}

LaunchLog::~LaunchLog() {
  for (cl_event e : events_)
    if (e) clReleaseEvent(e);
  g_active = nullptr;
}

LaunchLog* LaunchLog::active() { return g_active; }

cl_event* LaunchLog::add(const std::string& kernel, std::array<size_t, 2> global,
                         std::array<size_t, 2> local) {
  Launch l;
  l.kernel = kernel;
  l.items = global[0] * global[1];
  l.local = local[0] * local[1];
  l.groups = (global[0] / local[0]) * (global[1] / local[1]);
  launches_.push_back(l);
  events_.push_back(nullptr);
  return &events_.back();
}

std::vector<LaunchLog::Launch> LaunchLog::take() {
  for (size_t i = 0; i < events_.size(); ++i) {
    cl_event e = events_[i];
    if (!e) continue;
    LGN_CL_CHECK(clWaitForEvents(1, &e));
    cl_ulong start = 0, end = 0;
    if (clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof(start), &start, nullptr) ==
            CL_SUCCESS &&
        clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof(end), &end, nullptr) == CL_SUCCESS &&
        end >= start)
      launches_[i].seconds = double(end - start) * 1e-9;
    clReleaseEvent(e);
  }
  events_.clear();
  std::vector<Launch> out;
  out.swap(launches_);
  return out;
}

}  // namespace lorgnette::cl
