// OpenCL platform and device discovery, and the `--device` selection rule (index or name
// substring; by default the first GPU, else the first device, which is PoCL on a plain machine).
#pragma once
#include <CL/cl.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lorgnette::cl {

struct DeviceInfo {
  int index = 0;  // position in list_devices()
  cl_platform_id platform = nullptr;
  cl_device_id id = nullptr;
  std::string platform_name;
  std::string name;
  std::string vendor;
  std::string version;         // CL_DEVICE_VERSION
  std::string driver_version;  // CL_DRIVER_VERSION
  std::string c_version;       // CL_DEVICE_OPENCL_C_VERSION
  bool is_gpu = false;
  bool is_cpu = false;
  uint32_t compute_units = 0;
  uint64_t global_mem_bytes = 0;
  uint64_t local_mem_bytes = 0;
  size_t max_work_group_size = 0;

  std::string type_name() const { return is_gpu ? "GPU" : is_cpu ? "CPU" : "other"; }
  // One line for logs and reports: "[0] pthread-skylake (PoCL 3.1, CPU, 2 CU)".
  std::string summary() const;
};

// Every device of every platform. Throws with install advice when no platform exists.
std::vector<DeviceInfo> list_devices();

// spec: "" (default rule), a decimal index into list_devices(), or a case-insensitive substring of
// the device, vendor or platform name. Throws with the list of devices when nothing matches.
DeviceInfo select_device(const std::string& spec);

}  // namespace lorgnette::cl
