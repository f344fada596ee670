#include "relight/rank_limit.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "lighting/spec_parsing.h"
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

void RankLimit::applyTo(ModelRelighter& relighter) const {
  if (kind_ == Kind::Rank) relighter.setMaxRank(rank_);
  if (kind_ == Kind::Fraction) relighter.setRankFraction(fraction_);
}

}  // namespace acpca
