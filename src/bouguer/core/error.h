#pragma once
// Errors a user can cause (bad files, bad values) are exceptions of this one type; the message
// already names the place ("scene.json:12: ..." or "spectrum.csv: row 4: ...") and reads as one
// line. Internal invariants are assertions, not Errors.
#include <fmt/format.h>

#include <stdexcept>
#include <string>

namespace bouguer {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A value on the command line that cannot work (an output path that cannot be written): the
// command line exits 2 for these, 1 for every other Error.
class UsageError : public Error {
 public:
  using Error::Error;
};

template <typename... Args>
[[noreturn]] void fail_usage(fmt::format_string<Args...> format, Args&&... args) {
  throw UsageError(fmt::format(format, std::forward<Args>(args)...));
}

template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) {
  throw Error(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace bouguer
