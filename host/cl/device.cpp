// Device discovery through the ICD loader; selection by index or name substring.
#include "host/cl/device.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "host/cl/error.h"

namespace lorgnette::cl {
namespace {

constexpr const char* kNoPlatformAdvice =
    "No OpenCL platform found. Install one: on Debian `sudo apt-get install pocl-opencl-icd` "
    "(portable CPU device), or the NVIDIA driver's `nvidia-opencl-icd` for an NVIDIA GPU; "
    "`clinfo -l` should then list a device.";

std::string device_string(cl_device_id d, cl_device_info what) {
  size_t n = 0;
  LGN_CL_CHECK(clGetDeviceInfo(d, what, 0, nullptr, &n));
  std::string s(n, '\0');
  LGN_CL_CHECK(clGetDeviceInfo(d, what, n, s.data(), nullptr));
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return s;
}

template <class T>
T device_value(cl_device_id d, cl_device_info what) {
  T v{};
  LGN_CL_CHECK(clGetDeviceInfo(d, what, sizeof(T), &v, nullptr));
  return v;
}

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  size_t n = 0;
  LGN_CL_CHECK(clGetPlatformInfo(p, what, 0, nullptr, &n));
  std::string s(n, '\0');
  LGN_CL_CHECK(clGetPlatformInfo(p, what, n, s.data(), nullptr));
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

std::string DeviceInfo::summary() const {
  return fmt::format("[{}] {} ({}, {}, {} CU, {:.1f} GiB, {})", index, name, platform_name, type_name(),
                     compute_units, global_mem_bytes / double(1ull << 30), version);
}

std::vector<DeviceInfo> list_devices() {
  cl_uint np = 0;
  cl_int err = clGetPlatformIDs(0, nullptr, &np);
  if (err == -1001 /* CL_PLATFORM_NOT_FOUND_KHR */ || np == 0) throw std::runtime_error(kNoPlatformAdvice);
  LGN_CL_CHECK(err);
  std::vector<cl_platform_id> platforms(np);
  LGN_CL_CHECK(clGetPlatformIDs(np, platforms.data(), nullptr));
  std::vector<DeviceInfo> out;
  for (cl_platform_id p : platforms) {
    cl_uint nd = 0;
    if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &nd) != CL_SUCCESS || nd == 0) continue;
    std::vector<cl_device_id> ids(nd);
    LGN_CL_CHECK(clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, nd, ids.data(), nullptr));
    for (cl_device_id d : ids) {
      DeviceInfo info;
      info.index = static_cast<int>(out.size());
      info.platform = p;
      info.id = d;
      info.platform_name = platform_string(p, CL_PLATFORM_NAME);
      info.name = device_string(d, CL_DEVICE_NAME);
      info.vendor = device_string(d, CL_DEVICE_VENDOR);
      info.version = device_string(d, CL_DEVICE_VERSION);
      info.driver_version = device_string(d, CL_DRIVER_VERSION);
      info.c_version = device_string(d, CL_DEVICE_OPENCL_C_VERSION);
      auto type = device_value<cl_device_type>(d, CL_DEVICE_TYPE);
      info.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
      info.is_cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
      info.compute_units = device_value<cl_uint>(d, CL_DEVICE_MAX_COMPUTE_UNITS);
      info.global_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_GLOBAL_MEM_SIZE);
      info.local_mem_bytes = device_value<cl_ulong>(d, CL_DEVICE_LOCAL_MEM_SIZE);
      info.max_work_group_size = device_value<size_t>(d, CL_DEVICE_MAX_WORK_GROUP_SIZE);
      out.push_back(std::move(info));
    }
  }
  if (out.empty()) throw std::runtime_error(kNoPlatformAdvice);
  return out;
}

DeviceInfo select_device(const std::string& spec) {
  std::vector<DeviceInfo> all = list_devices();
  if (spec.empty()) {
    auto gpu = std::find_if(all.begin(), all.end(), [](const DeviceInfo& d) { return d.is_gpu; });
    return gpu != all.end() ? *gpu : all.front();
  }
  bool numeric = std::all_of(spec.begin(), spec.end(), [](unsigned char c) { return std::isdigit(c); });
  if (numeric) {
    size_t i = std::stoul(spec);
    if (i < all.size()) return all[i];
  } else {
    std::string needle = lower(spec);
    for (const DeviceInfo& d : all) {
      if (lower(d.name).find(needle) != std::string::npos ||
          lower(d.vendor).find(needle) != std::string::npos ||
          lower(d.platform_name).find(needle) != std::string::npos)
        return d;
    }
  }
  std::string listing;
  for (const DeviceInfo& d : all) listing += "\n  " + d.summary();
  throw std::runtime_error(
      fmt::format("No OpenCL device matches --device '{}'. Use an index or part of a name from `lorgnette "
                  "devices`:{}",
                  spec, listing));
}

}  // namespace lorgnette::cl
