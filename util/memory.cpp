#include "dacrt/util/memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

namespace dacrt {

namespace {

// The first number in the file (or after `key` on its line), or UINT64_MAX ("max", missing).
uint64_t read_number(const char* path, const std::string& key = "") {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (!key.empty() && line.rfind(key, 0) != 0) continue;
    std::istringstream fields(key.empty() ? line : line.substr(key.size()));
    uint64_t v = 0;
    if (fields >> v) return v;
    return std::numeric_limits<uint64_t>::max();
  }
  return std::numeric_limits<uint64_t>::max();
}

}  // namespace

uint64_t available_memory() {
  constexpr uint64_t none = std::numeric_limits<uint64_t>::max();
  uint64_t available = none;
  const uint64_t kib = read_number("/proc/meminfo", "MemAvailable:");
  if (kib != none) available = kib * 1024;
  const uint64_t limit = read_number("/sys/fs/cgroup/memory.max");
  const uint64_t used = read_number("/sys/fs/cgroup/memory.current");
  if (limit != none && used != none)
    available = std::min(available, limit > used ? limit - used : 0);
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) {
    const uint64_t vm_kib = read_number("/proc/self/status", "VmSize:");
    const uint64_t vm = vm_kib == none ? 0 : vm_kib * 1024;
    available = std::min<uint64_t>(available, as.rlim_cur > vm ? as.rlim_cur - vm : 0);
  }
  return available;
}

std::string format_bytes(uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
  char text[32];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return text;
}

}  // namespace dacrt
