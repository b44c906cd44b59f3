#include "bouguer/media/scattering_library.h"

namespace bouguer {

const std::vector<ScatteringLibraryEntry>& scattering_media() {
  static const std::vector<ScatteringLibraryEntry> entries;
  return entries;
}

const ScatteringLibraryEntry* find_scattering_medium(std::string_view name) {
  for (const ScatteringLibraryEntry& e : scattering_media())
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> scattering_medium_names() {
  std::vector<std::string> names;
  for (const ScatteringLibraryEntry& e : scattering_media()) names.push_back(e.name);
  return names;
}

}  // namespace bouguer
