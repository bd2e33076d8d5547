// A record of kernel launches for profiling: while a LaunchLog is alive, every cl::Kernel launch
// appends its kernel name, work-group and work-item counts and (on a queue created with
// profiling) its event, so a benchmark can report the device time and the parallelism of each
// kernel of a training step. One log at a time; the product never creates one.
#pragma once
#include <CL/cl.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "host/cl/handles.h"

namespace lorgnette::cl {

class LaunchLog {
 public:
  struct Launch {
    std::string kernel;
    size_t groups = 0;     // work-groups in the launch
    size_t items = 0;      // work-items (global size)
    size_t local = 0;      // work-items per group
    double seconds = 0.0;  // device time (end - start); 0 without a profiling queue
  };

  LaunchLog();  // becomes the active log; throws std::logic_error when another one is active
  ~LaunchLog();
  LaunchLog(const LaunchLog&) = delete;
  LaunchLog& operator=(const LaunchLog&) = delete;

  static LaunchLog* active();
  // Called by Kernel::launch2d: records the launch and returns where to put its event.
  cl_event* add(const std::string& kernel, std::array<size_t, 2> global, std::array<size_t, 2> local);
  // The launches since the last take(), with their device times (waits for their events).
  std::vector<Launch> take();

 private:
  std::vector<Launch> launches_;
  std::vector<cl_event> events_;  // owned; released by take() and the destructor
};

}  // namespace lorgnette::cl
