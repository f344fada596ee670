#pragma once
// Parsing of the small text specs users type (--env sun:..., --rotate ...).
#include <atomic>
#include <string>

namespace acpca {

/// The whole of `text` as a finite number; otherwise a ParameterError naming
/// the parameter, the whole spec it came from (e.g. rotation '1,x') and the bad part.
double parseFiniteNumber(const std::string& text, const std::string& parameter,
                         const std::string& spec);

/// A value given as a number (Python, a CLI flag) refused as its text would
/// be: ParameterError "parameter 'nan': 'nan' is not a finite number".
void requireFinite(double value, const std::string& parameter);

/// How many specs of each kind this process has parsed: what a run parses
/// is parsed once (a batch's plan, BatchPlan), and a test spies on these
/// counts to hold it so.
struct SpecParseCounts {
  std::atomic<long long> lights{0};       ///< parseLocalLight
  std::atomic<long long> lightSweeps{0};  ///< expandLightSweep
  std::atomic<long long> lightings{0};    ///< loadEnvironment
  std::atomic<long long> formats{0};      ///< imageFormatsFor
};
SpecParseCounts& specParseCounts();

}  // namespace acpca
