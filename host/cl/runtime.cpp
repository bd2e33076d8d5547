// Runtime: context, queue, and the two-level program cache. See runtime.h.
#include "host/cl/runtime.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "host/cl/error.h"
#include "host/cl/kernel_sources.h"

namespace lorgnette::cl {
namespace fs = std::filesystem;
namespace {

// FNV-1a 64: a cache key, not a security boundary; collisions would only cost a wrong binary,
// and the key includes the full source so any edit changes it.
uint64_t fnv1a(const std::string& s, uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string default_cache_dir() {
  if (const char* env = std::getenv("LORGNETTE_KERNEL_CACHE")) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME")) return std::string(xdg) + "/lorgnette/kernels";
  if (const char* home = std::getenv("HOME")) return std::string(home) + "/.cache/lorgnette/kernels";
  return "";
}

std::string build_log(cl_program program, cl_device_id device) {
  size_t n = 0;
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
  std::string log(n, '\0');
  clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
  while (!log.empty() && log.back() == '\0') log.pop_back();
  return log;
}

}  // namespace

void log_release_failure(const char* what, cl_int code) {
  spdlog::warn("releasing an OpenCL {} failed: {} ({})", what, error_name(code), code);
}

bool has_native_float_add(const DeviceInfo& device) {
  return device.platform_name.find("NVIDIA") != std::string::npos;
}

std::string default_build_options(const DeviceInfo& device, bool native_float_add) {
  std::string opts = "-cl-std=CL1.2";
  opts += device.is_gpu ? " -DLGN_DEVICE_GPU=1" : " -DLGN_DEVICE_GPU=0";
  if (native_float_add && has_native_float_add(device)) opts += " -DLGN_FLOAT_ADD_PTX=1";
  return opts;
}

Runtime::Runtime(const RuntimeOptions& options)
    : device_(select_device(options.device)),
      native_float_add_(options.native_float_add && has_native_float_add(device_)),
      mlp_grad_groups_(options.mlp_grad_groups) {
  cl_int err = CL_SUCCESS;
  cl_context_properties props[] = {CL_CONTEXT_PLATFORM,
                                   reinterpret_cast<cl_context_properties>(device_.platform), 0};
  context_ = ContextHandle(clCreateContext(props, 1, &device_.id, nullptr, nullptr, &err));
  LGN_CL_CHECK(err);
  cl_command_queue_properties qprops = options.profiling ? CL_QUEUE_PROFILING_ENABLE : 0;
  queue_ = QueueHandle(clCreateCommandQueue(context_.get(), device_.id, qprops, &err));
  LGN_CL_CHECK(err);
  cache_dir_ = options.cache_dir.empty() ? default_cache_dir() : options.cache_dir;
  if (cache_dir_ == "off") cache_dir_.clear();
  if (!cache_dir_.empty()) {
    std::error_code ec;
    fs::create_directories(cache_dir_, ec);
    if (ec) {
      spdlog::warn("kernel cache directory {} is not usable ({}); compiling without a disk cache", cache_dir_,
                   ec.message());
      cache_dir_.clear();
    }
  }
}

void Runtime::finish() const { LGN_CL_CHECK(clFinish(queue_.get())); }

cl_program Runtime::program(const std::string& root_file, const std::string& options) {
  const std::string defaults = default_build_options(device_, native_float_add_);
  std::string full_options = defaults + " " + options;
  AssembledSource source = assemble_kernel_source_mapped(root_file);
  std::string memo_key = root_file + "\n" + full_options;
  if (auto it = programs_.find(memo_key); it != programs_.end()) return it->second.get();

  uint64_t key = fnv1a(source.text);
  key = fnv1a(full_options, key);
  key = fnv1a(device_.name + "|" + device_.version + "|" + device_.driver_version, key);
  std::string path;
  if (!cache_dir_.empty()) path = fmt::format("{}/{:016x}.bin", cache_dir_, key);

  ProgramHandle prog;
  if (!path.empty() && fs::exists(path)) {
    try {
      prog = load_binary(path, full_options);
      ++disk_hits_;
    } catch (const std::exception& e) {
      spdlog::warn("ignoring unusable cached kernel binary {}: {}", path, e.what());
    }
  }
  if (!prog) {
    try {
      prog = build_from_source(source, full_options);
    } catch (const Error& e) {
      // A compiler that refuses the inline PTX float add: the compare-and-swap loop from now on. A
      // source that fails without it too throws its own error from the second build.
      if (!native_float_add_) throw;
      native_float_add_ = false;
      cl_program fallback = program(root_file, options);
      spdlog::warn("{}'s compiler refused the native float add (PTX red.add); using compare-and-swap: {}",
                   device_.name, e.what());
      return fallback;
    }
    ++compiled_;
    if (!path.empty()) store_binary(prog.get(), path);
  }
  cl_program raw = prog.get();
  programs_.emplace(memo_key, std::move(prog));
  return raw;
}

ProgramHandle Runtime::build_from_source(const AssembledSource& source, const std::string& options) {
  const char* text = source.text.c_str();
  size_t len = source.text.size();
  cl_int err = CL_SUCCESS;
  ProgramHandle prog(clCreateProgramWithSource(context_.get(), 1, &text, &len, &err));
  LGN_CL_CHECK(err);
  err = clBuildProgram(prog.get(), 1, &device_.id, options.c_str(), nullptr, nullptr);
  if (err != CL_SUCCESS) {
    throw Error(fmt::format("OpenCL kernel compilation failed on {} with options '{}':\n{}", device_.name,
                            options, map_build_log(build_log(prog.get(), device_.id), source.lines)),
                err);
  }
  return prog;
}

ProgramHandle Runtime::load_binary(const std::string& path, const std::string& options) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bin((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bin.empty()) throw std::runtime_error("empty file");
  const unsigned char* ptr = bin.data();
  size_t len = bin.size();
  cl_int status = CL_SUCCESS, err = CL_SUCCESS;
  ProgramHandle prog(clCreateProgramWithBinary(context_.get(), 1, &device_.id, &len, &ptr, &status, &err));
  LGN_CL_CHECK(err);
  LGN_CL_CHECK(status);
  LGN_CL_CHECK(clBuildProgram(prog.get(), 1, &device_.id, options.c_str(), nullptr, nullptr));
  return prog;
}

void Runtime::store_binary(cl_program program, const std::string& path) {
  size_t size = 0;
  if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof(size), &size, nullptr) != CL_SUCCESS ||
      size == 0)
    return;
  std::vector<unsigned char> bin(size);
  unsigned char* ptr = bin.data();
  if (clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof(ptr), &ptr, nullptr) != CL_SUCCESS) return;
  // Write then rename, so a concurrent reader never sees half a binary.
  std::string tmp = path + ".tmp" + std::to_string(reinterpret_cast<uintptr_t>(this));
  {
    std::ofstream out(tmp, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    out.close();  // checked after close: a full disk may show only when the buffer is flushed
    if (!out) {
      spdlog::warn("could not write kernel cache file {} (disk full?)", tmp);
      std::error_code ec;
      fs::remove(tmp, ec);
      return;
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace lorgnette::cl
