#pragma once
// The progress line long commands print: done/total, rate, elapsed and ETA.
// Libraries report progress through callbacks; the CLI shows it with this.
#include <functional>
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

/// A progress callback for a stage that may never run: its line starts at the
/// first report and finishes when done reaches total.
std::function<void(long long done, long long total)> stageProgress(std::string label,
                                                                   std::string unit, bool quiet);

}  // namespace acpca
