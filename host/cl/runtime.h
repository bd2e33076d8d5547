// The OpenCL runtime one command uses: a device, its context and in-order queue, and programs
// built from the embedded kernels with an in-memory and an on-disk binary cache (keyed by source,
// options, device and driver). Every module's host class borrows a Runtime&.
#pragma once
#include <map>
#include <memory>
#include <string>

#include "host/cl/device.h"
#include "host/cl/handles.h"
#include "host/cl/kernel_sources.h"

namespace lorgnette::cl {

struct RuntimeOptions {
  std::string device;      // --device spec (see select_device)
  std::string cache_dir;   // "" = $LORGNETTE_KERNEL_CACHE, else $XDG_CACHE_HOME/lorgnette/kernels,
                           // else ~/.cache/lorgnette/kernels; "off" disables the disk cache
  bool profiling = false;  // queue with CL_QUEUE_PROFILING_ENABLE
  // Float atomic adds with the device's own instruction where the kernels know one (NVIDIA's
  // OpenCL: PTX red.global.add.f32, -DLGN_FLOAT_ADD_PTX=1); false, or a compiler that refuses it:
  // the portable compare-and-swap loop. Benchmarks set it false to compare the two.
  bool native_float_add = true;
  // The MLP weight gradient's work-groups on a GPU (field::gpu_grad_groups): 0 = from the device's
  // compute units; N = at most N (benchmarks set 128, the old fixed split, to compare).
  uint32_t mlp_grad_groups = 0;
};

class Runtime {
 public:
  explicit Runtime(const RuntimeOptions& options = {});
  Runtime(const Runtime&) = delete;
  Runtime& operator=(const Runtime&) = delete;

  const DeviceInfo& device() const { return device_; }
  cl_context context() const { return context_.get(); }
  cl_command_queue queue() const { return queue_.get(); }
  void finish() const;

  // Builds (or fetches from cache) the program for an embedded root file with extra options
  // (e.g. "-DHASH_LEVELS=16"). On a compile error throws with the build log (file:line).
  cl_program program(const std::string& root_file, const std::string& options = "");

  // Whether programs are built with the device's own float atomic add: asked for (RuntimeOptions),
  // known for this device (has_native_float_add) and not refused by its compiler.
  bool native_float_add() const { return native_float_add_; }
  // RuntimeOptions::mlp_grad_groups as given (0: the kernels choose from the compute units).
  uint32_t mlp_grad_groups() const { return mlp_grad_groups_; }
  // Where binaries are cached ("" when disabled).
  const std::string& cache_dir() const { return cache_dir_; }
  // Counts for tests: how many programs were compiled from source vs loaded from disk.
  int compiled_count() const { return compiled_; }
  int disk_hits() const { return disk_hits_; }

 private:
  ProgramHandle build_from_source(const AssembledSource& source, const std::string& options);
  ProgramHandle load_binary(const std::string& path, const std::string& options);
  void store_binary(cl_program program, const std::string& path);

  DeviceInfo device_;
  bool native_float_add_ = false;
  uint32_t mlp_grad_groups_ = 0;
  ContextHandle context_;
  QueueHandle queue_;
  std::string cache_dir_;
  std::map<std::string, ProgramHandle> programs_;
  int compiled_ = 0;
  int disk_hits_ = 0;
};

// Whether the kernels know a float atomic add of the device's own (NVIDIA's platform: PTX).
bool has_native_float_add(const DeviceInfo& device);

// Default build options for every program (fast math is NOT used: tests compare with the host).
// native_float_add: -DLGN_FLOAT_ADD_PTX=1 on NVIDIA's platform (RuntimeOptions::native_float_add).
std::string default_build_options(const DeviceInfo& device, bool native_float_add = false);

}  // namespace lorgnette::cl
