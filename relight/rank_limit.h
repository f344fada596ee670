#pragma once
// A limit on each cluster's rank, parsed once where a user gives it (the
// CLI's --max-rank, Python's max_rank) and passed on as a value.
#include <string>
#include <vector>

namespace acpca {

class ModelRelighter;

class RankLimit {
 public:
  /// No limit: every basis.
  RankLimit() = default;
  /// "K" keeps each cluster's first K bases, a fraction in (0, 1) or a
  /// percentage ("50%") that share of each cluster's; "" is no limit. Throws a
  /// ParameterError ("maximum rank") for anything else.
  static RankLimit parse(const std::string& text);
  /// A number as parse reads one: a whole number a rank, else a fraction.
  static RankLimit ofNumber(double value);

  bool limited() const { return kind_ != Kind::None; }
  /// As the user wrote it ("" for none): messages and dataset.json.
  const std::string& text() const { return text_; }
  /// Sets the relighter's limit; no limit leaves it as it is.
  void applyTo(ModelRelighter& relighter) const;
  /// The ranks the limit leaves of each cluster's `ranks`.
  std::vector<int> activeRanks(const std::vector<int>& ranks) const;

 private:
  enum class Kind { None, Rank, Fraction };
  static RankLimit ofValue(double value, bool percent, const std::string& text);
  Kind kind_ = Kind::None;
  int rank_ = 0;
  double fraction_ = 1;
  std::string text_;
};

/// The cost metric per pixel at the relighter's current rank limit: the sum
/// over clusters of n_c (p_c + N) over the pixels ([Mahajan07] eq. 17/19, a
/// mean counted as a basis), which `compress` and `info` report at full ranks.
double costMetricPerPixel(const ModelRelighter& relighter);

/// Each rank cut to at most k (k < 0: unchanged).
std::vector<int> ranksUpTo(const std::vector<int>& ranks, int k);
/// Each rank r cut to ceil(fraction x r); throws UserError unless fraction is in [0, 1].
std::vector<int> ranksOfFraction(const std::vector<int>& ranks, double fraction);

}  // namespace acpca
