#pragma once
// Warnings: input that is merely imperfect and was accepted anyway (a map's
// tiny negative texels, say). Libraries report them here and carry on; the
// program decides where they go (the CLI prints them on stderr). Without a
// handler they are dropped.
#include <functional>
#include <string>
#include <vector>

namespace acpca {

using WarningHandler = std::function<void(const std::string&)>;

/// Installs the process's warning handler; returns the previous one.
WarningHandler setWarningHandler(WarningHandler handler);

/// Reports a warning to the handler (thread-safe; nothing without a handler).
void warn(const std::string& message);

/// While one lives, warnings raised on its thread are held here instead of
/// reported: work run in parallel (each task its own) passes them on after,
/// in input order, whatever the thread count. Nests; what is not taken is
/// dropped.
class HeldWarnings {
 public:
  HeldWarnings();
  ~HeldWarnings();
  HeldWarnings(const HeldWarnings&) = delete;
  HeldWarnings& operator=(const HeldWarnings&) = delete;
  /// The warnings held so far, in the order they were raised.
  std::vector<std::string> take() { return std::move(held_); }

 private:
  friend void warn(const std::string& message);
  HeldWarnings* outer_;
  std::vector<std::string> held_;
};

}  // namespace acpca
