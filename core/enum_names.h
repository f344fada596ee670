#pragma once
// One table per enum of names users type, so that parsing, printing and the
// list in an error message cannot drift apart.
#include <array>
#include <string>
#include <utility>

#include "core/error.h"

namespace acpca {

template <typename Enum, size_t Count>
class EnumNames {
 public:
  using Entry = std::pair<Enum, const char*>;
  constexpr EnumNames(const char* parameter, std::array<Entry, Count> entries)
      : parameter_(parameter), entries_(entries) {}

  const char* name(Enum value) const {
    for (const auto& [v, n] : entries_)
      if (v == value) return n;
    return "?";
  }
  /// The value named `text`; a ParameterError listing the names otherwise.
  Enum parse(const std::string& text) const {
    for (const auto& [v, n] : entries_)
      if (text == n) return v;
    throw ParameterError(parameter_, text, concat("is not one of ", list()));
  }
  const std::array<Entry, Count>& entries() const { return entries_; }
  std::string list() const {
    std::string out;
    for (const auto& [v, n] : entries_) out += (out.empty() ? "" : ", ") + std::string(n);
    return out;
  }

 private:
  const char* parameter_;
  std::array<Entry, Count> entries_;
};

}  // namespace acpca
