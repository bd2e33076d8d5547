// The OpenCL runtime layer on PoCL: device selection, build + disk cache, argument and launch
// checks, and compile errors that name the file and line.
#include <filesystem>

#include <gtest/gtest.h>

#include "host/cl/device.h"
#include "host/cl/kernel.h"
#include "host/cl/kernel_sources.h"
#include "host/cl/runtime.h"
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
