#pragma once
// Where a value given to the SceneBuilder came from, for its messages: the file and the place in
// it (a key path such as "objects[2].shape.radius", whatever the front end's format), or a
// command-line option. Every error about the value is one line naming both:
//   scene.json: objects[2].shape.radius: must be a positive length (got -1 m)
//   --spp: must be between 1 and 1048576 (got 0)
// A command-line source fails with a UsageError (the command line exits 2 for those).
#include <fmt/format.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>

#include "bouguer/core/error.h"

namespace bouguer {

struct Source {
  std::filesystem::path file;  // the file the value was read from (empty for the command line)
  std::string path;            // the place in it; the option's name for the command line
  bool command_line = false;

  static Source option(std::string name) { return {{}, std::move(name), true}; }

  Source operator/(const std::string& key) const { return {file, path.empty() ? key : path + "." + key, command_line}; }
  Source operator[](std::size_t i) const { return {file, fmt::format("{}[{}]", path, i), command_line}; }

  // "scene.json: objects[2]" (or "--spp"): the prefix of every message about the value.
  std::string name() const {
    if (command_line) return path;
    return fmt::format("{}: {}", file.string(), path.empty() ? "(top level)" : path);
  }

  template <typename... Args>
  [[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) const {
    const std::string message = fmt::format("{}: {}", name(), fmt::format(f, std::forward<Args>(args)...));
    if (command_line) throw UsageError(message);
    throw Error(message);
  }

  // A file named in the source, relative to the source's own folder.
  std::filesystem::path resolve(const std::string& relative) const {
    const std::filesystem::path p(relative);
    return p.is_absolute() ? p : file.parent_path() / p;
  }
};

}  // namespace bouguer
