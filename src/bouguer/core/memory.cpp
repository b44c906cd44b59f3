#include "bouguer/core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

// "Name:   1234 kB" lines of /proc/meminfo or /proc/self/status, in bytes (kUnknown if absent),
// read in one pass.
template <std::size_t K>
std::array<std::uint64_t, K> proc_kb_fields(const char* file, const std::array<std::string_view, K>& names) {
  std::array<std::uint64_t, K> values;
  values.fill(kUnknown);
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    for (std::size_t k = 0; k < K; ++k)
      if (line.compare(0, names[k].size(), names[k]) == 0) {
        unsigned long long kb = 0;
        if (std::sscanf(line.c_str() + names[k].size(), " %llu", &kb) == 1) values[k] = kb * 1024;
      }
  return values;
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
  std::uint64_t available = proc_kb_fields<1>("/proc/meminfo", {"MemAvailable:"})[0];
  const auto [vm, data] = proc_kb_fields<2>("/proc/self/status", {"VmSize:", "VmData:"});
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

void require_memory(std::uint64_t bytes, std::string_view what, std::uint64_t available) {
  if (available == kUnknown || bytes <= available) return;
  fail("{} needs about {} of memory; {} is available", what, format_bytes(bytes), format_bytes(available));
}

}  // namespace bouguer
