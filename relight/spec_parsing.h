#pragma once
// Parsing of the small text specs users type (--env sun:..., --rotate ...).
#include <string>

namespace acpca {

/// The whole of `text` as a finite number; otherwise a UserError that starts
/// with `context` (e.g. "--rotate '1,x'") and names the bad part.
double parseFiniteNumber(const std::string& text, const std::string& context);

}  // namespace acpca
