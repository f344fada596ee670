#pragma once
// Dimensionality against patch area for a few patch centres ([Mahajan07] Fig. 7),
// shared by `analyze` and `bench scaling`.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "cluster/dimensionality.h"

namespace acpca {

/// Patch sides tried: areas from 16 to 4096 pixels in steps of about sqrt(2).
inline const std::vector<int> kAnalysisSides{4, 6, 8, 11, 16, 23, 32, 45, 64};
/// Slopes are fitted over patches of this many occupied pixels.
inline constexpr double kSlopeAreaMin = 16, kSlopeAreaMax = 4096;
/// The large-patch slope starts here: below it the paper's flat, sub-linear
/// regime (the omega_H term of eq. 12) pulls the full-range slope down.
inline constexpr double kLargeAreaMin = 256;

struct CentreDimensionality {
  int x = 0, y = 0;
  std::vector<double> area{}, dimensionality{};  ///< per patch tried (pixels, eigenvalues)
  PowerLaw fit{};                                ///< over areas in [kSlopeAreaMin, kSlopeAreaMax]
  PowerLaw largeFit{};                           ///< over areas in [kLargeAreaMin, kSlopeAreaMax]
};

struct DimensionalityAnalysis {
  std::vector<CentreDimensionality> centres;
  double meanSlope = 0;       ///< over the centres with a fit
  double meanLargeSlope = 0;  ///< the same for the large-patch fits
};

/// "X,Y" strings as pixel positions; throws UserError naming a bad one.
std::vector<std::pair<int, int>> parseCentres(const std::vector<std::string>& texts);

/// With no centres given, five occupied pixels where an 8x8 patch needs the
/// most bases, spread over the occupied region.
DimensionalityAnalysis analyzeDimensionality(const TransportReader& transport,
                                             std::vector<std::pair<int, int>> centres,
                                             const std::vector<int>& sides, double energy,
                                             const std::function<void(const std::string&)>& log);

/// dimensionality.csv (centre, x, y, side, area, dimensionality) and slopes.csv.
void writeDimensionalityCsv(const DimensionalityAnalysis& analysis, const std::string& dir);

/// v with `digits` decimals, or "-" when not finite.
std::string formatFixed(double v, int digits);

}  // namespace acpca
