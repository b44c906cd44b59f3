#include "bouguer/io/output_set.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cerrno>
#include <cstring>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"

namespace bouguer {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// ".png, .exr or .pfm"
std::string alternatives(std::span<const std::string_view> extensions) {
  std::string text;
  for (std::size_t i = 0; i < extensions.size(); ++i) {
    if (i > 0) text += i + 1 == extensions.size() ? " or " : ", ";
    text += extensions[i];
  }
  return text;
}

// Why `path` cannot be written as a new file, or empty when it can.
std::string why_not_writable(const fs::path& path, std::span<const std::string_view> extensions) {
  if (path.filename().empty()) return "not a file name";
  std::error_code ec;
  const fs::file_status target = fs::status(path, ec);
  if (fs::is_directory(target)) return "it is a folder";
  if (fs::exists(target) && !fs::is_regular_file(target)) return "it is not a regular file";
  const std::string ext = lower_extension(path);
  if (!extensions.empty() && std::find(extensions.begin(), extensions.end(), ext) == extensions.end())
    return ext.empty() ? fmt::format("no file type (use {})", alternatives(extensions))
                       : fmt::format("unknown file type '{}' (use {})", ext, alternatives(extensions));
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  const fs::file_status status = fs::status(folder, ec);
  if (status.type() == fs::file_type::not_found) return fmt::format("folder '{}' does not exist", folder.string());
  if (ec) return fmt::format("cannot reach folder '{}': {}", folder.string(), ec.message());
  if (!fs::is_directory(status)) return fmt::format("'{}' is not a folder", folder.string());
  if (::faccessat(AT_FDCWD, folder.c_str(), W_OK | X_OK, AT_EACCESS) != 0)
    return fmt::format("folder '{}' is not writable ({})", folder.string(), std::strerror(errno));
  return {};
}

// A writer's message about its temporary file, told about the target instead, without repeating
// the target's name at the front.
std::string about_target(std::string message, const fs::path& temp, const fs::path& target) {
  const std::string from = temp.string(), to = target.string();
  for (std::size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
    message.replace(at, from.size(), to);
  if (message.starts_with(to + ": ")) message.erase(0, to.size() + 2);
  return message;
}

}  // namespace

void OutputSet::add(std::string option, fs::path path, std::span<const std::string_view> extensions) {
  if (const std::string why = why_not_writable(path, extensions); !why.empty())
    fail_usage("{} {}: {}", option, path.string(), why);
  std::error_code ec;
  fs::path identity = fs::weakly_canonical(path, ec);
  if (ec) identity = path.lexically_normal();
  for (const Output& earlier : outputs_)
    if (earlier.identity == identity)
      fail_usage("{} {}: the same file as {} {}", option, path.string(), earlier.option, earlier.path.string());
  outputs_.push_back({std::move(option), std::move(path), std::move(identity)});
}

void OutputSet::write_all(const Writers& writers) const {
  std::vector<fs::path> temps;
  temps.reserve(outputs_.size());
  const auto remove_temporaries = [&temps](std::size_t from) {
    std::error_code ec;
    for (std::size_t i = from; i < temps.size(); ++i) fs::remove(temps[i], ec);
  };
  for (const Output& out : outputs_) {
    const auto writer = writers.find(out.option);
    assert(writer != writers.end() && "every option added to an OutputSet needs a writer");
    temps.push_back(temporary_path_for(out.path));
    try {
      writer->second(temps.back());
    } catch (const Error& e) {
      remove_temporaries(0);
      fail("{} {}: {}; no output was written", out.option, out.path.string(),
           about_target(e.what(), temps.back(), out.path));
    } catch (...) {
      remove_temporaries(0);
      throw;
    }
  }
  // Every file is complete; renames within a folder that was checked writable do not fail unless
  // the folder changes under the run.
  for (std::size_t i = 0; i < outputs_.size(); ++i) {
    std::error_code ec;
    fs::rename(temps[i], outputs_[i].path, ec);
    if (ec) {
      remove_temporaries(i);
      fail("{} {}: cannot write: {}; {}", outputs_[i].option, outputs_[i].path.string(), ec.message(),
           i == 0 ? "no output was written" : fmt::format("only the {} output(s) before it were written", i));
    }
  }
}

}  // namespace bouguer
