#include "bouguer/io/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>

#include "bouguer/core/error.h"

namespace bouguer {
namespace fs = std::filesystem;

fs::path temporary_path_for(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string name = fmt::format(".{}.tmp-{}-{}{}", target.stem().string(), ::getpid(), counter++,
                                       target.extension().string());
  return target.parent_path() / name;
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  if (target.filename().empty()) fail("{}: not a file name", target.string());
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) fail("{}: cannot write: folder '{}' does not exist", target.string(), folder.string());
  if (fs::is_directory(target, ec)) fail("{}: cannot write: it is a folder", target.string());
  const fs::path temp = temporary_path_for(target);
  try {
    write(temp);
    fs::rename(temp, target);
  } catch (const fs::filesystem_error& e) {
    fs::remove(temp, ec);
    fail("{}: cannot write: {}", target.string(), e.code().message());
  } catch (...) {
    fs::remove(temp, ec);
    throw;
  }
}

void write_bytes_atomically(const fs::path& target, std::string_view bytes) {
  write_atomically(target, [&](const fs::path& temp) {
    std::ofstream f(temp, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f) fail("{}: cannot write", target.string());
  });
}

}  // namespace bouguer
