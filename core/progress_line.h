#pragma once
// The progress line long commands print: done/total, rate, elapsed and ETA.
// Libraries report progress through callbacks; the CLI shows it with this.
#include <string>

#include "core/stopwatch.h"

namespace acpca {

/// A progress line on stderr: done/total, rate, ETA; rewritten in place on a
/// terminal, one line every few seconds otherwise; silent when quiet.
class Progress {
 public:
  Progress(std::string label, std::string unit, bool quiet);
  void update(long long done, long long total);
  void finish();

 private:
  std::string label_, unit_;
  bool quiet_, tty_;
  Stopwatch sinceStart_, sinceLastPrint_;
  bool printed_ = false;
};

}  // namespace acpca
