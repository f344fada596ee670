#pragma once
// The project's two error channels (docs/architecture.md):
//  - UserError: bad input from the user (a file, a field, a value). main() prints
//    its message and exits non-zero. ParameterError is the kind a library throws
//    for an option it was given: it names the parameter in the library's own
//    terms, and the CLI renders it with the flag that set it.
//  - ACPCA_CHECK: an internal invariant; failing it is a bug, and the message
//    prints the condition and the values involved.
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

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

/// A bad value of a named parameter: "tolerance '1.5': must be in (0, 1]".
/// `parameter` is the library's name for it (a field of an options struct, in
/// words); a front end that knows which flag set it says so instead.
class ParameterError : public UserError {
 public:
  ParameterError(std::string parameter, std::string value, std::string problem)
      : UserError(render(parameter, value, problem)),
        parameter_(std::move(parameter)),
        value_(std::move(value)),
        problem_(std::move(problem)) {}
  template <typename Value>
  ParameterError(std::string parameter, const Value& value, std::string problem)
      : ParameterError(std::move(parameter), concat(value), std::move(problem)) {}

  const std::string& parameter() const { return parameter_; }
  const std::string& value() const { return value_; }
  const std::string& problem() const { return problem_; }
  /// The same message with `name` (e.g. "--tolerance") in place of the parameter.
  std::string messageFor(const std::string& name) const { return render(name, value_, problem_); }

 private:
  static std::string render(const std::string& name, const std::string& value,
                            const std::string& problem) {
    return value.empty() ? concat(name, ": ", problem) : concat(name, " '", value, "': ", problem);
  }
  std::string parameter_, value_, problem_;
};

/// A file that could not be written (full disk, removed directory, no
/// permission): names the file and what the system said.
class WriteError : public UserError {
 public:
  using UserError::UserError;
};

[[noreturn]] void failCheck(const char* condition, const char* file, int line,
                            const std::string& detail);

}  // namespace acpca

#define ACPCA_CHECK(condition, ...)                                                     \
  do {                                                                                  \
    if (!(condition))                                                                   \
      ::acpca::failCheck(#condition, __FILE__, __LINE__, ::acpca::concat(__VA_ARGS__)); \
  } while (0)
