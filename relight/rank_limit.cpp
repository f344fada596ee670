#include "relight/rank_limit.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "lighting/spec_parsing.h"
#include "model/model_summary.h"
#include "relight/model_relighter.h"

namespace acpca {

RankLimit RankLimit::ofValue(double value, bool percent, const std::string& text) {
  RankLimit limit;
  limit.text_ = text;
  if (percent) {
    if (value < 0 || value > 100)
      throw ParameterError("maximum rank", text, "a percentage is 0..100");
    limit.kind_ = Kind::Fraction;
    limit.fraction_ = value / 100;
  } else if (value == std::floor(value)) {
    if (value < 0) throw ParameterError("maximum rank", text, "a rank is >= 0");
    limit.kind_ = Kind::Rank;
    limit.rank_ = static_cast<int>(std::min(value, 1e9));
  } else {
    if (value < 0 || value > 1)
      throw ParameterError("maximum rank", text, "a fraction is in (0, 1)");
    limit.kind_ = Kind::Fraction;
    limit.fraction_ = value;
  }
  return limit;
}

RankLimit RankLimit::parse(const std::string& text) {
  if (text.empty()) return {};
  const bool percent = text.back() == '%';
  const double value =
      parseFiniteNumber(percent ? text.substr(0, text.size() - 1) : text, "maximum rank", text);
  return ofValue(value, percent, text);
}

RankLimit RankLimit::ofNumber(double value) {
  if (!std::isfinite(value))
    throw ParameterError("maximum rank", shortestNumberText(value), "is not a finite number");
  return ofValue(value, false, shortestNumberText(value));
}

std::vector<int> RankLimit::activeRanks(const std::vector<int>& ranks) const {
  if (kind_ == Kind::Rank) return ranksUpTo(ranks, rank_);
  if (kind_ == Kind::Fraction) return ranksOfFraction(ranks, fraction_);
  return ranks;
}

std::vector<int> ranksUpTo(const std::vector<int>& ranks, int k) {
  std::vector<int> active = ranks;
  if (k >= 0)
    for (int& r : active) r = std::min(r, k);
  return active;
}

std::vector<int> ranksOfFraction(const std::vector<int>& ranks, double fraction) {
  if (!(fraction >= 0 && fraction <= 1))
    throw UserError(concat("rank fraction ", fraction, " is not in [0, 1]"));
  std::vector<int> active = ranks;
  for (int& r : active) r = std::min(r, static_cast<int>(std::ceil(fraction * r - 1e-9)));
  return active;
}

void RankLimit::applyTo(ModelRelighter& relighter) const {
  if (kind_ == Kind::Rank) relighter.setMaxRank(rank_);
  if (kind_ == Kind::Fraction) relighter.setRankFraction(fraction_);
}

double costMetricPerPixel(const ModelRelighter& relighter) {
  const PackedModel& m = *relighter.packed();
  std::vector<std::int64_t> rowOffsets(m.ranks.size() + 1, 0);
  for (int c : m.clusterOfRow()) ++rowOffsets[c + 1];
  for (size_t c = 1; c < rowOffsets.size(); ++c) rowOffsets[c] += rowOffsets[c - 1];
  const std::vector<int>& active = relighter.activeRanks();
  const std::vector<std::int32_t> ranks(active.begin(), active.end());
  return m.rows() ? clustersCost(ranks, rowOffsets, m.hasMean, m.globalBases) / m.rows() : 0;
}

}  // namespace acpca
