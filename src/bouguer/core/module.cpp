#include "bouguer/core/module.h"

#include <dlfcn.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <vector>

namespace bouguer {

void* load_module_entry(const std::string& built_path, const char* symbol, bool global, std::string& problem) {
  namespace fs = std::filesystem;
  std::vector<std::string> candidates = {built_path};
  std::array<char, 4096> self{};
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  if (n > 0)
    candidates.push_back((fs::path(std::string(self.data(), static_cast<std::size_t>(n))).parent_path() /
                          fs::path(built_path).filename())
                             .string());
  for (const std::string& path : candidates) {
    void* handle = dlopen(path.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
    const std::string why = handle ? path + ": not Bouguer's module (no " + symbol + ")" : dlerror();
    if (handle)
      if (void* entry = dlsym(handle, symbol)) return entry;
    problem += (problem.empty() ? "" : "; ") + why;  // (each place tried: the first is the build's)
  }
  return nullptr;
}

}  // namespace bouguer
