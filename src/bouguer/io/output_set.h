#pragma once
// The files one command writes, checked before the work and written all or nothing after it.
//   OutputSet outputs;
//   outputs.add("-o", "shot.png", kImageExtensions);  // checked now: fails in milliseconds, not after a render
//   ... the long work ...
//   outputs.write_all({{"-o", [&](const std::filesystem::path& p) { write_image(p, film); }}});
// write_all writes every output to a temporary file in its target's folder first and renames them
// all into place only when every write succeeded: if one fails, no existing file is replaced, the
// temporaries are removed and the Error names the option and path of the output that failed.
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace bouguer {

class OutputSet {
 public:
  // Writes one output to the path it is given (a temporary beside the target with the target's
  // extension); throws (an Error naming the path) when it cannot.
  using Writer = std::function<void(const std::filesystem::path& path)>;
  using Writers = std::map<std::string, Writer, std::less<>>;  // by option

  // Checks now that `path` can be written for `option` (named in every message, e.g. "-o"): it
  // names a file, not an existing folder; its extension is one of `extensions` (lower case with
  // the dot, matched in any case; empty: any name); its folder exists, is a folder and is
  // writable; no earlier output has the same path. Otherwise throws UsageError "OPTION PATH: why".
  void add(std::string option, std::filesystem::path path, std::span<const std::string_view> extensions = {});

  // Writes each output with the writer of its option (every option added needs one), then renames
  // them all into place; see above. Throws Error "OPTION PATH: why; no output was written".
  void write_all(const Writers& writers) const;

 private:
  struct Output {
    std::string option;
    std::filesystem::path path, identity;  // identity: absolute and normalised, for duplicates
  };
  std::vector<Output> outputs_;
};

}  // namespace bouguer
