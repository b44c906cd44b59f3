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

template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> format, Args&&... args) {
  throw Error(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace bouguer
