// The OpenCL runtime layer on PoCL: device selection, build + disk cache, argument and launch
// checks, and compile errors that name the file and line.
#include "host/cl/runtime.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "host/cl/device.h"
#include "host/cl/kernel.h"
#include "host/cl/kernel_sources.h"
#include "kernels/common/selftest_types.h"

using namespace lorgnette;
namespace fs = std::filesystem;

TEST(Device, ListsAtLeastOneDeviceAndSelectsByIndexAndName) {
  auto all = cl::list_devices();
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(cl::select_device("0").name, all[0].name);
  EXPECT_EQ(cl::select_device(all[0].name.substr(0, 6)).index, all[0].index);
}

TEST(Device, UnknownDeviceNamesTheChoices) {
  try {
    cl::select_device("no-such-device-xyz");
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("no-such-device-xyz"), std::string::npos);
    EXPECT_NE(msg.find("[0]"), std::string::npos) << msg;
  }
}

TEST(KernelSources, ResolvesIncludesWithLineDirectives) {
  std::string src = cl::assemble_kernel_source("common/selftest.cl");
  EXPECT_NE(src.find("#line 1 \"common/selftest_types.h\""), std::string::npos);
  EXPECT_NE(src.find("#line 1 \"common/cl_compat.h\""), std::string::npos);
  EXPECT_THROW(cl::assemble_kernel_source("nope/missing.cl"), std::runtime_error);
}

TEST(KernelSources, LineMapPointsEveryAssembledLineAtItsOrigin) {
  cl::AssembledSource a = cl::assemble_kernel_source_mapped("common/selftest.cl");
  EXPECT_EQ(a.text, cl::assemble_kernel_source("common/selftest.cl"));
  std::vector<std::string> lines;
  std::istringstream in(a.text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(static_cast<int>(lines.size()), a.lines.size());
  int mapped = 0, error_line = 0;
  for (int i = 1; i <= a.lines.size(); ++i) {
    cl::SourceLocation loc;
    if (!a.lines.find(i, &loc)) {  // only the added #line directives are unmapped
      EXPECT_EQ(lines[i - 1].rfind("#line ", 0), 0u) << "assembled line " << i << ": " << lines[i - 1];
      continue;
    }
    ++mapped;
    std::istringstream file(cl::embedded_kernel_files().at(loc.file));
    std::string original;
    for (int k = 0; k < loc.line; ++k) std::getline(file, original);
    if (original.find("#pragma once") != std::string::npos) original.clear();  // blanked, line kept
    EXPECT_EQ(lines[i - 1], original) << loc.file << ":" << loc.line;
    if (lines[i - 1].find("undefined_name_xyz") != std::string::npos) {
      error_line = i;
      EXPECT_EQ(loc.file, "common/selftest.cl");
      EXPECT_EQ(loc.line, 9);
    }
  }
  EXPECT_GT(mapped, 20);
  ASSERT_GT(error_line, 9);  // the includes come first
  // What NVIDIA's compiler (which ignores #line) reports for that line.
  std::string log = "<kernel>:" + std::to_string(error_line) + ":3: error: use of undeclared identifier";
  EXPECT_EQ(cl::map_build_log(log, a.lines), "common/selftest.cl:9:3: error: use of undeclared identifier");
}

TEST(KernelSources, BuildLogReferencesWithoutAFileAreMapped) {
  // Assembled lines: 1 = a directive, 2..51 = lines 1..50 of common/x.h, 52 = a directive,
  // 53.. = lines 7.. of hashgrid/k.cl.
  cl::LineMap map;
  map.push("common/x.h", 0);
  for (int i = 1; i <= 50; ++i) map.push("common/x.h", i);
  map.push("hashgrid/k.cl", 0);
  for (int i = 7; i <= 20; ++i) map.push("hashgrid/k.cl", i);
  const std::string log =
      "<kernel>:53:3: error: use of undeclared identifier 'x'\n"
      "    x += 1;\n"
      "    ^\n"
      "<kernel>:2:10: note: declared here\n"
      "<source>:54:1: warning: unused\n"
      ":60:5: error: no file at all\n"
      "common/selftest.cl:9:3: error: a file name is kept\n"
      "ratio 1:2:3 and (see <kernel>:999:1, out of range; <kernel>:52:1 is a directive)\n";
  const std::string want =
      "hashgrid/k.cl:7:3: error: use of undeclared identifier 'x'\n"
      "    x += 1;\n"
      "    ^\n"
      "common/x.h:1:10: note: declared here\n"
      "hashgrid/k.cl:8:1: warning: unused\n"
      "hashgrid/k.cl:14:5: error: no file at all\n"
      "common/selftest.cl:9:3: error: a file name is kept\n"
      "ratio 1:2:3 and (see <kernel>:999:1, out of range; <kernel>:52:1 is a directive)\n";
  EXPECT_EQ(cl::map_build_log(log, map), want);
  EXPECT_EQ(cl::map_build_log("", map), "");
}

TEST(Runtime, AxpyMatchesHostAndSecondRuntimeHitsDiskCache) {
  std::string cache = std::string(LORGNETTE_TEST_TMP) + "/cache-axpy";
  fs::remove_all(cache);
  const uint32_t n = 1000;
  std::vector<float> x(n), y(n);
  for (uint32_t i = 0; i < n; ++i) {
    x[i] = 0.5f * i;
    y[i] = 1.0f - i;
  }
  for (int round = 0; round < 2; ++round) {
    cl::Runtime rt({"", cache, false});
    cl::Kernel k(rt.program("common/selftest.cl"), "selftest_axpy");
    cl::Buffer<float> bx(rt, x), by(rt, y);
    SelftestParams p{n, 2.0f};
    k.args(p, bx, by).launch(rt, n, 64);
    auto out = by.read(rt);
    for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(out[i], 2.0f * x[i] + y[i]) << i;
    EXPECT_EQ(rt.compiled_count(), round == 0 ? 1 : 0);
    EXPECT_EQ(rt.disk_hits(), round == 0 ? 0 : 1);
  }
}

TEST(Runtime, WrongArgumentCountAndBadLocalSizeAreClearErrors) {
  cl::Runtime rt({"", "off", false});
  cl::Kernel k(rt.program("common/selftest.cl"), "selftest_axpy");
  cl::Buffer<float> b(rt, 4);
  EXPECT_THROW(k.args(b, b), cl::Error);
  SelftestParams p{4, 1.0f};
  k.args(p, b, b);
  try {
    k.launch(rt, 4, 1u << 20);
    FAIL();
  } catch (const cl::Error& e) {
    EXPECT_NE(std::string(e.what()).find("local size 1048576"), std::string::npos) << e.what();
  }
}

TEST(Runtime, CompileErrorReportsFileAndLine) {
  cl::Runtime rt({"", "off", false});
  try {
    rt.program("common/selftest.cl", "-DLGN_SELFTEST_BREAK");
    FAIL() << "expected a build failure";
  } catch (const cl::Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("common/selftest.cl:9"), std::string::npos) << msg;
    EXPECT_NE(msg.find("undefined_name_xyz"), std::string::npos) << msg;
  }
}

TEST(Runtime, NativeFloatAddOnlyOnNvidiasPlatform) {
  // The hash backward's PTX float add (-DLGN_FLOAT_ADD_PTX=1) is asked of NVIDIA's compiler alone,
  // and only while the runtime allows it; every other device keeps the compare-and-swap loop.
  cl::DeviceInfo nvidia;
  nvidia.platform_name = "NVIDIA CUDA";
  nvidia.is_gpu = true;
  cl::DeviceInfo pocl;
  pocl.platform_name = "Portable Computing Language";
  pocl.is_cpu = true;
  const std::string ptx = "-DLGN_FLOAT_ADD_PTX=1";
  EXPECT_NE(cl::default_build_options(nvidia, true).find(ptx), std::string::npos);
  EXPECT_EQ(cl::default_build_options(nvidia, false).find(ptx), std::string::npos);
  EXPECT_EQ(cl::default_build_options(pocl, true).find(ptx), std::string::npos);
  EXPECT_TRUE(cl::has_native_float_add(nvidia));
  EXPECT_FALSE(cl::has_native_float_add(pocl));
  // The runtime reports what its programs use: the native add only where the device has one and the
  // options ask for it (PoCL here: never).
  cl::RuntimeOptions cas;
  cas.native_float_add = false;
  cl::Runtime rt(cl::RuntimeOptions{});
  EXPECT_EQ(rt.native_float_add(), cl::has_native_float_add(rt.device()));
  EXPECT_FALSE(cl::Runtime(cas).native_float_add());
}
