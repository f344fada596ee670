#include "eval/dimensionality_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "core/error.h"
#include "core/table.h"
#include "eval/eval_report.h"
#include "lighting/spec_parsing.h"

namespace acpca {

std::string formatFixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

std::vector<std::pair<int, int>> parseCentres(const std::vector<std::string>& texts) {
  std::vector<std::pair<int, int>> out;
  for (const auto& t : texts) {
    const auto comma = t.find(',');
    if (comma == std::string::npos) throw ParameterError("patch centre", t, "expected X,Y");
    const double x = parseFiniteNumber(t.substr(0, comma), "patch centre", t);
    const double y = parseFiniteNumber(t.substr(comma + 1), "patch centre", t);
    if (x < 0 || y < 0 || x != std::floor(x) || y != std::floor(y) || x > 1e6 || y > 1e6)
      throw ParameterError("patch centre", t, "X and Y are pixel positions (whole numbers >= 0)");
    out.push_back({int(x), int(y)});
  }
  return out;
}

namespace {

/// The occupied pixel nearest to (x, y).
std::pair<int, int> nearestOccupied(const TransportHeader& h, double x, double y) {
  const int w = h.camera.size.width;
  double best = std::numeric_limits<double>::infinity();
  std::pair<int, int> out{0, 0};
  for (int p : h.pixels) {
    const double dx = p % w - x, dy = p / w - y, d = dx * dx + dy * dy;
    if (d < best) best = d, out = {p % w, p / w};
  }
  return out;
}

/// Five centres where light transport is busiest: on a 7x7 grid over the
/// occupied region's bounding box, the points whose 8x8 patch needs the most
/// bases, kept at least a fifth of the box apart (a uniform wall or sky tells
/// nothing about how dimensionality grows).
std::vector<std::pair<int, int>> defaultCentres(const TransportReader& transport, double energy) {
  const TransportHeader& h = transport.header();
  const int w = h.camera.size.width;
  int x0 = w, x1 = 0, y0 = h.camera.size.height, y1 = 0;
  for (int p : h.pixels) {
    x0 = std::min(x0, p % w), x1 = std::max(x1, p % w);
    y0 = std::min(y0, p / w), y1 = std::max(y1, p / w);
  }
  struct Candidate {
    std::pair<int, int> at;
    int dimensionality;
  };
  std::vector<Candidate> candidates;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      const auto at =
          nearestOccupied(h, x0 + (i + 0.5) / 7 * (x1 - x0), y0 + (j + 0.5) / 7 * (y1 - y0));
      candidates.push_back(
          {at, patchDimensionality(readSquarePatch(transport, at.first, at.second, 8),
                                   transport.rowLength(), energy)});
    }
  std::stable_sort(
      candidates.begin(), candidates.end(),
      [](const Candidate& a, const Candidate& b) { return a.dimensionality > b.dimensionality; });
  const double apart = std::max(x1 - x0, y1 - y0) / 5.0;
  std::vector<std::pair<int, int>> chosen;
  for (const auto& c : candidates) {
    const bool farEnough = std::all_of(chosen.begin(), chosen.end(), [&](const auto& o) {
      return std::hypot(o.first - c.at.first, o.second - c.at.second) >= apart;
    });
    if (farEnough) chosen.push_back(c.at);
    if (chosen.size() == 5) break;
  }
  return chosen;
}

}  // namespace

DimensionalityAnalysis analyzeDimensionality(const TransportReader& transport,
                                             std::vector<std::pair<int, int>> centres,
                                             const std::vector<int>& sides, double energy,
                                             const std::function<void(const std::string&)>& log) {
  const TransportHeader& h = transport.header();
  const int w = h.camera.size.width, ht = h.camera.size.height;
  for (const auto& [x, y] : centres)
    if (x >= w || y >= ht)
      throw ParameterError("patch centre", concat(x, ",", y),
                           concat("outside the ", w, "x", ht, " image"));
  if (centres.empty() && !h.pixels.empty()) centres = defaultCentres(transport, energy);
  DimensionalityAnalysis out;
  double slopeSum = 0, largeSum = 0;
  int fitted = 0, largeFitted = 0;
  for (const auto& [x, y] : centres) {
    CentreDimensionality c{x, y};
    long long lastRows = -1;
    for (int side : sides) {
      const PatchRows patch = readSquarePatch(transport, x, y, side);
      if (patch.rows == lastRows) continue;  // clipped by the image: the same patch again
      lastRows = patch.rows;
      c.area.push_back(double(patch.rows));
      c.dimensionality.push_back(patchDimensionality(patch, transport.rowLength(), energy));
    }
    const auto fitOver = [&](double lo) {
      std::vector<double> area, dims;
      for (size_t i = 0; i < c.area.size(); ++i)
        if (c.area[i] >= lo && c.area[i] <= kSlopeAreaMax)
          area.push_back(c.area[i]), dims.push_back(c.dimensionality[i]);
      return fitPowerLaw(area, dims);
    };
    c.fit = fitOver(kSlopeAreaMin);
    c.largeFit = fitOver(kLargeAreaMin);
    if (std::isfinite(c.fit.slope)) slopeSum += c.fit.slope, ++fitted;
    if (std::isfinite(c.largeFit.slope)) largeSum += c.largeFit.slope, ++largeFitted;
    if (log)
      log(concat("centre ", x, ",", y, ": slope ", formatFixed(c.fit.slope, 3), " over ",
                 c.fit.points, " patches (", formatFixed(c.largeFit.slope, 3), " from ",
                 kLargeAreaMin, " pixels)"));
    out.centres.push_back(std::move(c));
  }
  out.meanSlope = fitted ? slopeSum / fitted : NAN;
  out.meanLargeSlope = largeFitted ? largeSum / largeFitted : NAN;
  return out;
}

void writeDimensionalityCsv(const DimensionalityAnalysis& analysis, const std::string& dir) {
  Table dims({"centre", "x", "y", "area", "dimensionality"});
  Table slopes({"centre", "x", "y", "slope", "scale", "points", "large_patch_slope"});
  for (size_t i = 0; i < analysis.centres.size(); ++i) {
    const auto& c = analysis.centres[i];
    const long long centre = static_cast<long long>(i), x = c.x, y = c.y;
    for (size_t k = 0; k < c.area.size(); ++k)
      dims.add({centre, x, y, c.area[k], c.dimensionality[k]});
    slopes.add({centre, x, y, formatFixed(c.fit.slope, 4), formatFixed(c.fit.scale, 4),
                (long long)c.fit.points, formatFixed(c.largeFit.slope, 4)});
  }
  namespace fs = std::filesystem;
  dims.writeCsv((fs::path(dir) / "dimensionality.csv").string());
  slopes.writeCsv((fs::path(dir) / "slopes.csv").string());
}

}  // namespace acpca
