#pragma once
// printf-style formatting into a std::string, for tables and summaries.
#include <string>

namespace acpca {

/// The text printf would print for `format` and the values.
std::string formatted(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// Human-readable byte count (e.g. "1.20 GiB").
std::string formatBytes(double bytes);

}  // namespace acpca
