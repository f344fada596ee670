#include "model/model.h"

#include "core/error.h"
#include "core/half.h"
#include "core/text.h"
#include "model/cost_model.h"
#include "model/model_summary.h"

#include <algorithm>

namespace acpca {

CoeffPrecision parseBasisPrecision(const std::string& text) {
  const CoeffPrecision p = kCoeffPrecisionNames.parse(text);
  if (p == CoeffPrecision::I8)
    throw ParameterError("basis precision", text, "is not one of f32, f16");
  return p;
}

CoeffPrecision parseCoeffPrecision(const std::string& text) {
  return kCoeffPrecisionNames.parse(text);
}

const char* coeffPrecisionName(CoeffPrecision p) {
  return kCoeffPrecisionNames.name(p);
}

double clustersCost(const std::vector<std::int32_t>& ranks,
                    const std::vector<std::int64_t>& rowOffsets, bool hasMean, int globalBases) {
  double cost = 0;
  for (size_t c = 0; c < ranks.size(); ++c)
    cost +=
        clusterCost(ranks[c] + (hasMean ? 1 : 0), rowOffsets[c + 1] - rowOffsets[c], globalBases);
  return cost;
}

double Model::totalCost() const {
  return clustersCost(ranks, rowOffsets, hasMean, globalBases());
}

ClusterValues Model::clusterValues(int c) const {
  ClusterValues v;
  v.rank = ranks[c];
  v.rows = rowOffsets[c + 1] - rowOffsets[c];
  v.globalBases = globalBases();
  v.precision = precision;
  v.bases = bases.data() + basisOffsets[c];
  v.mean = means.data() + static_cast<long long>(c) * v.globalBases;
  const long long at = coefficientOffsets[c];
  v.coefficients = precision == CoeffPrecision::F32 ? static_cast<const void*>(coeffF32.data() + at)
                   : precision == CoeffPrecision::F16
                       ? static_cast<const void*>(coeffF16.data() + at)
                       : static_cast<const void*>(coeffI8.data() + at);
  v.scale = coeffScale.data() + firstBasisIndex(c);
  return v;
}

float Model::coefficient(int c, long long r, int k) const {
  const long long i = coefficientOffsets[c] + r * ranks[c] + k;
  switch (precision) {
    case CoeffPrecision::F32:
      return coeffF32[i];
    case CoeffPrecision::F16: {
      float v;
      halfToFloat(&coeffF16[i], &v, 1);
      return v;
    }
    default:
      return coeffI8[i] * coeffScale[firstBasisIndex(c) + k];
  }
}

std::vector<int> Model::clusterOfRow() const {
  std::vector<int> out(static_cast<size_t>(rows()), -1);
  for (int c = 0; c < clusters(); ++c)
    for (auto r = rowOffsets[c]; r < rowOffsets[c + 1]; ++r) out[clusterRows[r]] = c;
  return out;
}

long long frameBytesOf(CoeffPrecision coefficients, CoeffPrecision bases, long long basisValues,
                       long long meanValues, long long coefficientValues,
                       long long globalBasisValues) {
  const long long coefficientBytes = storedBytes(coefficients);
  const long long basisBytes = storedBytes(bases);
  return (basisValues + meanValues) * basisBytes + coefficientValues * coefficientBytes +
         globalBasisValues * 4;
}

long long Model::frameBytes() const {
  return frameBytesOf(precision, basisPrecision, static_cast<long long>(bases.size()),
                      hasMean ? static_cast<long long>(means.size()) : 0, coefficientOffsets.back(),
                      static_cast<long long>(globalBasis.size()));
}

std::map<int, int> rankHistogram(const std::vector<std::int32_t>& ranks) {
  std::map<int, int> counts;
  for (int r : ranks) ++counts[r];
  return counts;
}

std::map<int, int> rankHistogram(const Model& m) {
  return rankHistogram(m.ranks);
}

std::string rankSummary(const Model& m) {
  return rankSummary(m.ranks);
}

std::string rankSummary(const std::vector<std::int32_t>& ranks) {
  if (ranks.empty()) return "no clusters";
  std::vector<int> sorted(ranks.begin(), ranks.end());
  std::sort(sorted.begin(), sorted.end());
  std::string out = concat("min ", sorted.front(), ", median ", sorted[sorted.size() / 2], ", max ",
                           sorted.back(), ";");
  // Buckets 0, 1, 2-4, 5-16, 17-64, ...: a few numbers for any spread of ranks.
  int low = 0, high = 0;
  size_t i = 0;
  while (i < sorted.size()) {
    size_t count = 0;
    while (i < sorted.size() && sorted[i] <= high) ++i, ++count;
    if (count > 0)
      out += low == high ? concat(" ", low, ": ", count) : concat(" ", low, "-", high, ": ", count);
    if (i < sorted.size()) out += count > 0 ? "," : "";
    low = high + 1;
    high = high == 0 ? 1 : 4 * high;
  }
  if (out.back() == ',') out.pop_back();
  return out;
}

std::string describeInWords(const Model& m) {
  return concat(m.method, ", ", m.clusters(), " clusters, N = ", m.globalBases(), ", cost ",
                m.totalCost(), " (", m.costPerPixel(), " per pixel), transport error ",
                m.transportError, ", ", formatBytes(m.frameBytes()), " read per frame, ",
                m.compressSeconds, " s");
}

nlohmann::json summaryJson(const Model& m) {
  return {{"method", m.method},
          {"clusters", m.clusters()},
          {"global_bases", m.globalBases()},
          {"total_cost", m.totalCost()},
          {"cost_per_pixel", m.costPerPixel()},
          {"transport_error", m.transportError},
          {"global_energy_kept", m.globalEnergyKept},
          {"bytes_per_frame", m.frameBytes()},
          {"seconds", m.compressSeconds}};
}

}  // namespace acpca
