#include "core/table.h"

#include <cmath>
#include <sstream>
#include <type_traits>

#include "core/atomic_file.h"
#include "core/error.h"

namespace acpca {

void Table::add(std::vector<Cell> row) {
  ACPCA_CHECK(row.size() == columns_.size(), row.size(), " cells for ", columns_.size(),
              " columns");
  rows_.push_back(std::move(row));
}

std::string csvNumber(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(", \"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

std::string Table::csvHeader() const {
  std::string out;
  for (size_t c = 0; c < columns_.size(); ++c) {
    if (c) out += ",";
    out += csvField(columns_[c]);
  }
  return out + "\n";
}

std::string Table::csvRow(size_t i) const {
  std::string out;
  const auto& row = rows_.at(i);
  for (size_t c = 0; c < row.size(); ++c) {
    if (c) out += ",";
    if (const auto* d = std::get_if<double>(&row[c]))
      out += csvNumber(*d);
    else if (const auto* n = std::get_if<long long>(&row[c]))
      out += std::to_string(*n);
    else
      out += csvField(std::get<std::string>(row[c]));
  }
  return out + "\n";
}

std::string Table::csv() const {
  std::string out = csvHeader();
  for (size_t i = 0; i < rows_.size(); ++i) out += csvRow(i);
  return out;
}

nlohmann::json Table::json() const {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& row : rows_) {
    nlohmann::json object = nlohmann::json::object();
    for (size_t c = 0; c < row.size(); ++c)
      std::visit(
          [&](const auto& v) {
            if constexpr (std::is_same_v<std::decay_t<decltype(v)>, double>)
              object[columns_[c]] = finiteOrNull(v);
            else
              object[columns_[c]] = v;
          },
          row[c]);
    out.push_back(object);
  }
  return out;
}

void Table::writeCsv(const std::string& path) const {
  writeTextFile(path, csv());
}

}  // namespace acpca
