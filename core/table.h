#pragma once
// One table, two renderings: the same rows as CSV (a header line, then one
// line a row) and as JSON (an array of objects keyed by column). Reports build
// a Table and write it both ways instead of formatting each file by hand.
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

namespace acpca {

class Table {
 public:
  /// A number (NAN and infinities print as an empty CSV field and JSON null),
  /// a whole number, or text.
  using Cell = std::variant<double, long long, std::string>;

  explicit Table(std::vector<std::string> columns) : columns_(std::move(columns)) {}

  /// Appends a row; it must have one cell per column.
  void add(std::vector<Cell> row);

  const std::vector<std::string>& columns() const { return columns_; }
  size_t rows() const { return rows_.size(); }

  /// Header line and rows; text is quoted where it holds a comma, space, quote or newline.
  std::string csv() const;
  /// The header line alone, and row i's line alone (each with its newline).
  std::string csvHeader() const;
  std::string csvRow(size_t i) const;
  /// [{column: value, ...}, ...].
  nlohmann::json json() const;
  /// Writes csv() atomically; throws WriteError naming the path.
  void writeCsv(const std::string& path) const;

 private:
  std::vector<std::string> columns_;
  std::vector<std::vector<Cell>> rows_;
};

/// v with six significant digits as CSV writes it; empty when not finite.
std::string csvNumber(double v);
/// s quoted for CSV when it holds a comma, space, quote or newline.
std::string csvField(const std::string& s);
/// v as JSON, or null when it is NAN or infinite.
nlohmann::json finiteOrNull(double v);

}  // namespace acpca
