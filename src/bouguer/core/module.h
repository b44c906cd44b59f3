#pragma once
// Bouguer's own loadable modules (libbouguer_vdb.so, libbouguer_mpi.so): shared libraries that
// keep a heavy dependency out of the program's start, loaded with dlopen on first use.
#include <string>

namespace bouguer {

// The entry point `symbol` of the module the build put at `built_path`, looked for there and
// then beside the running program (an installed or copied build). nullptr when neither loads,
// with `problem` saying why. `global`: the module's symbols serve the libraries it loads in turn
// (Open MPI's components need its own).
void* load_module_entry(const std::string& built_path, const char* symbol, bool global, std::string& problem);

}  // namespace bouguer
