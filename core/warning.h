#pragma once
// Warnings: input that is merely imperfect and was accepted anyway (a map's
// tiny negative texels, say). Libraries report them here and carry on; the
// program decides where they go (the CLI prints them on stderr). Without a
// handler they are dropped.
#include <functional>
#include <string>

namespace acpca {

using WarningHandler = std::function<void(const std::string&)>;

/// Installs the process's warning handler; returns the previous one.
WarningHandler setWarningHandler(WarningHandler handler);

/// Reports a warning to the handler (thread-safe; nothing without a handler).
void warn(const std::string& message);

}  // namespace acpca
