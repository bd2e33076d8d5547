// What a timing needs beside its wall seconds to be compared with another run's: the process's CPU
// time, which unlike wall time does not grow when other programs share the cores, and the machine it
// ran on, since machines of one name differ (memory, clocks, neighbours): a figure is only compared
// with one from the same machine.
#pragma once
#include <string>

namespace lorgnette {

// User plus system CPU seconds of every thread of this process so far (getrusage RUSAGE_SELF).
double process_cpu_seconds();

struct MachineInfo {
  std::string cpu;          // the CPU's model name ("unknown" where the system does not say)
  unsigned cpus = 0;        // logical CPUs online
  double memory_gib = 0.0;  // physical memory
  double load = -1.0;       // 1-minute load average when read (-1: not available)

  // "AMD EPYC, 2 CPUs, 23.4 GiB, load 0.21"
  std::string summary() const;
};

// The machine this process runs on, read now (Linux: /proc/cpuinfo, sysconf, getloadavg).
MachineInfo machine_info();

}  // namespace lorgnette
