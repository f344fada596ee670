#pragma once
// printf-style formatting into a std::string, for tables and summaries.
#include <string>
#include <vector>

namespace acpca {

/// The text printf would print for `format` and the values.
std::string formatted(const char* format, ...) __attribute__((format(printf, 1, 2)));

/// Edits (insertions, deletions, substitutions) that turn a into b: how close
/// a mistyped name is to a known one.
size_t editDistance(const std::string& a, const std::string& b);

/// The pieces of `text` between separators, empty ones kept ("a,,b": a, "",
/// b); empty text gives no piece.
std::vector<std::string> splitText(const std::string& text, char separator);

/// The shortest text that reads back as the same double (std::to_chars): a
/// number written into a spec or a manifest gives the very number again.
std::string shortestNumberText(double v);

/// Human-readable byte count (e.g. "1.20 GiB").
std::string formatBytes(double bytes);

}  // namespace acpca
