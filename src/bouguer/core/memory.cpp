#include "bouguer/core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

// A "Name:   1234 kB" line of /proc/meminfo or /proc/self/status, in bytes.
std::uint64_t proc_kb_field(const char* file, std::string_view name) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.compare(0, name.size(), name) == 0) {
      unsigned long long kb = 0;
      if (std::sscanf(line.c_str() + name.size(), " %llu", &kb) == 1) return kb * 1024;
    }
  return kUnknown;
}

// What a resource limit leaves above what the process already uses of it.
std::uint64_t left_under(int resource, std::uint64_t used) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return kUnknown;
  const auto cap = static_cast<std::uint64_t>(limit.rlim_cur);
  return cap > used ? cap - used : 0;
}

}  // namespace

std::uint64_t memory_available_bytes() {
  std::uint64_t available = proc_kb_field("/proc/meminfo", "MemAvailable:");
  const std::uint64_t vm = proc_kb_field("/proc/self/status", "VmSize:");
  const std::uint64_t data = proc_kb_field("/proc/self/status", "VmData:");
  if (vm != kUnknown) available = std::min(available, left_under(RLIMIT_AS, vm));
  if (data != kUnknown) available = std::min(available, left_under(RLIMIT_DATA, data));
  return available;
}

std::string format_bytes(std::uint64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1024.0 * 1024 * 1024) return fmt::format("{:.1f} GiB", b / (1024.0 * 1024 * 1024));
  if (b >= 1024.0 * 1024) return fmt::format("{:.0f} MiB", b / (1024.0 * 1024));
  return fmt::format("{:.0f} KiB", b / 1024.0);
}

void require_memory(std::uint64_t bytes, std::string_view what) {
  const std::uint64_t available = memory_available_bytes();
  if (available == kUnknown || bytes <= available) return;
  fail("{} needs about {} of memory; {} is available", what, format_bytes(bytes), format_bytes(available));
}

}  // namespace bouguer
