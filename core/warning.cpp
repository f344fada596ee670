#include "core/warning.h"

#include <mutex>

namespace acpca {

namespace {
std::mutex& handlerMutex() {
  static std::mutex m;
  return m;
}
WarningHandler& currentHandler() {
  static WarningHandler h;
  return h;
}
thread_local HeldWarnings* innermostHeld = nullptr;
}  // namespace

HeldWarnings::HeldWarnings() : outer_(innermostHeld) {
  innermostHeld = this;
}

HeldWarnings::~HeldWarnings() {
  innermostHeld = outer_;
}

WarningHandler setWarningHandler(WarningHandler handler) {
  std::lock_guard lock(handlerMutex());
  std::swap(currentHandler(), handler);
  return handler;
}

void warn(const std::string& message) {
  if (innermostHeld) return innermostHeld->held_.push_back(message);
  std::lock_guard lock(handlerMutex());
  if (currentHandler()) currentHandler()(message);
}

}  // namespace acpca
