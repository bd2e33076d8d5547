// Process CPU time and the machine's description; see machine.h.
#include "host/util/machine.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>

namespace lorgnette {
namespace {

double seconds(const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); }

// The first "model name" line of /proc/cpuinfo; "unknown" without one (other systems, some ARM CPUs).
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const size_t start = line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) return line.substr(start);
    break;
  }
  return "unknown";
}

}  // namespace

double process_cpu_seconds() {
  rusage u{};
  if (getrusage(RUSAGE_SELF, &u) != 0) return 0.0;
  return seconds(u.ru_utime) + seconds(u.ru_stime);
}

std::string MachineInfo::summary() const {
  std::string s = fmt::format("{}, {} CPUs, {:.1f} GiB", cpu, cpus, memory_gib);
  if (load >= 0.0) s += fmt::format(", load {:.2f}", load);
  return s;
}

MachineInfo machine_info() {
  MachineInfo m;
  m.cpu = cpu_model();
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  m.cpus = cpus > 0 ? unsigned(cpus) : 0u;
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  if (pages > 0 && page > 0) m.memory_gib = double(pages) * double(page) / double(1ull << 30);
  double load[1];
  if (getloadavg(load, 1) == 1) m.load = load[0];
  return m;
}

}  // namespace lorgnette
