#include "core/progress_line.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

namespace acpca {

Progress::Progress(std::string label, std::string unit, bool quiet)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      quiet_(quiet),
      tty_(isatty(STDERR_FILENO)) {}

namespace {
std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  const long s = std::lround(seconds);
  char buffer[32];
  if (s >= 3600)
    std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", s / 3600, (s / 60) % 60);
  else if (s >= 60)
    std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
  else
    std::snprintf(buffer, sizeof buffer, "%lds", s);
  return buffer;
}
}  // namespace

void Progress::update(long long done, long long total) {
  if (quiet_) return;
  if (done < total && sinceLastPrint_.seconds() < (tty_ ? 0.25 : 5.0)) return;
  sinceLastPrint_.restart();
  const double elapsed = sinceStart_.seconds();
  const double rate = elapsed > 0 ? done / elapsed : 0;
  const double eta = rate > 0 ? (total - done) / rate : NAN;
  char line[256];
  std::snprintf(line, sizeof line, "%s: %lld/%lld %s (%.1f%%), %.3g %s/s, elapsed %s, ETA %s",
                label_.c_str(), done, total, unit_.c_str(), total ? 100.0 * done / total : 100.0,
                rate, unit_.c_str(), formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  std::cerr << (tty_ ? "\r" : "") << line << (tty_ ? "\033[K" : "\n") << std::flush;
  printed_ = true;
}

void Progress::finish() {
  if (!quiet_ && printed_ && tty_) std::cerr << "\n";
}

std::function<void(long long, long long)> stageProgress(std::string label, std::string unit,
                                                        bool quiet) {
  auto line = std::make_shared<std::optional<Progress>>();
  return [=](long long done, long long total) {
    if (!*line) line->emplace(label, unit, quiet);
    (*line)->update(done, total);
    if (done == total) (*line)->finish();
  };
}

}  // namespace acpca
