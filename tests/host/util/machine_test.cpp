// Process CPU time and the machine's description (host/util/machine.h), against the system's own
// clocks and counters.
#include "host/util/machine.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <ctime>
#include <thread>

namespace lorgnette {
namespace {

double reference_cpu_seconds() {  // POSIX's process CPU clock, a second way to read the same time
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// Spins until `seconds` of this process's CPU time (by the reference clock) have passed.
void burn(double seconds) {
  const double end = reference_cpu_seconds() + seconds;
  volatile double x = 1.0;
  while (reference_cpu_seconds() < end)
    for (int i = 0; i < 1000; ++i) x = std::sqrt(x + 1.0);
}

TEST(ProcessCpu, CountsTheCpuTimeOfEveryThreadAsThePosixClockDoes) {
  const double ours0 = process_cpu_seconds(), ref0 = reference_cpu_seconds();
  std::thread other([] { burn(0.1); });  // a second thread's time counts too
  burn(0.1);
  other.join();
  const double ours = process_cpu_seconds() - ours0, ref = reference_cpu_seconds() - ref0;
  EXPECT_GE(ref, 0.1);
  // getrusage and the CPU clock read the same counters at microsecond and nanosecond resolution;
  // 10 ms covers the reads' order and a scheduler tick.
  EXPECT_NEAR(ours, ref, 0.01);
}

TEST(Machine, DescribesTheCpusMemoryAndLoadTheSystemReports) {
  const MachineInfo m = machine_info();
  EXPECT_EQ(long(m.cpus), sysconf(_SC_NPROCESSORS_ONLN));
  EXPECT_NEAR(m.memory_gib,
              double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE)) / double(1ull << 30), 1e-9);
  EXPECT_GT(m.memory_gib, 0.0);
  EXPECT_FALSE(m.cpu.empty());
  double load[1];
  ASSERT_EQ(getloadavg(load, 1), 1);
  EXPECT_GE(m.load, 0.0);
  const std::string s = m.summary();
  EXPECT_EQ(s.rfind(m.cpu + ", " + std::to_string(m.cpus) + " CPUs, ", 0), 0u) << s;
  EXPECT_NE(s.find(" GiB, load "), std::string::npos) << s;
}

TEST(Machine, SummaryLeavesOutALoadItCouldNotRead) {
  MachineInfo m;
  m.cpu = "Test CPU";
  m.cpus = 2;
  m.memory_gib = 23.44;
  EXPECT_EQ(m.summary(), "Test CPU, 2 CPUs, 23.4 GiB");
  m.load = 0.214;
  EXPECT_EQ(m.summary(), "Test CPU, 2 CPUs, 23.4 GiB, load 0.21");
}

}  // namespace
}  // namespace lorgnette
