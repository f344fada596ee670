#pragma once
// The project's two error channels (docs/architecture.md):
//  - UserError: bad input from the user (a file, a field, a value). main() prints
//    its message and exits non-zero.
//  - ACPCA_CHECK: an internal invariant; failing it is a bug, and the message
//    prints the condition and the values involved.
#include <sstream>
#include <stdexcept>
#include <string>

namespace acpca {

/// An error in what the user gave us; the message names the input and the problem.
class UserError : public std::runtime_error {
 public:
  explicit UserError(const std::string& message) : std::runtime_error(message) {}
};

/// Builds a message from streamable parts: concat("size ", w, "x", h).
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

[[noreturn]] void failCheck(const char* condition, const char* file, int line,
                            const std::string& detail);

}  // namespace acpca

#define ACPCA_CHECK(condition, ...)                                                     \
  do {                                                                                  \
    if (!(condition))                                                                   \
      ::acpca::failCheck(#condition, __FILE__, __LINE__, ::acpca::concat(__VA_ARGS__)); \
  } while (0)
