#pragma once
// Bouguer's own loadable modules (libbouguer_vdb.so, libbouguer_texture.so, libbouguer_mpi.so):
// shared libraries that keep a heavy dependency out of the program's start, loaded with dlopen on
// first use.
#include <mutex>
#include <string>

namespace bouguer {

// The entry point `symbol` of the module the build put at `built_path`, looked for there and
// then beside the running program (an installed or copied build). nullptr when neither loads,
// with `problem` saying why. `global`: the module's symbols serve the libraries it loads in turn
// (Open MPI's components need its own).
void* load_module_entry(const std::string& built_path, const char* symbol, bool global, std::string& problem);

// The API a module's entry point returns (a struct whose `version` is 1), loaded once: nullptr
// when it cannot be, with `problem` saying why.
template <typename Api>
const Api* module_api_once(const char* built_path, const char* symbol, bool global, std::string& problem) {
  static const Api* api = nullptr;
  static std::string why;
  static std::once_flag once;
  std::call_once(once, [&] {
    using Entry = const Api* (*)();
    if (const auto entry = reinterpret_cast<Entry>(load_module_entry(built_path, symbol, global, why))) {
      api = entry();
      if (api->version != 1) {
        why = std::string(built_path) + ": not Bouguer's module (version " + std::to_string(api->version) + ")";
        api = nullptr;
      }
    }
  });
  problem = why;
  return api;
}

}  // namespace bouguer
