#include "eval/quantization_study.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "cluster/compress.h"
#include "cluster/quantization.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "core/table.h"
#include "eval/dimensionality_study.h"
#include "eval/error_measures.h"
#include "eval/eval_report.h"
#include "eval/method_sweep.h"
#include "eval/sh_transport.h"
#include "relight/model_relighter.h"
#include "transport/row_stream.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

const CoeffPrecision kStorages[] = {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8};

/// Image error of one stored variant over the evaluation set.
struct StoredError {
  double error = 0;  ///< RMS over maps of the relative L2
  double psnr = 0;   ///< mean over maps
  long long bytes = 0;
};

/// The set's error and mean PSNR of one stored variant (no timing).
StoredError measure(const EvaluationData& data, long long bytes,
                    const std::function<void(const LatticeLighting&, float*)>& relight) {
  SweepResult r;
  measureMaps(data, r, 0, relight);
  double meanPsnr = 0;
  for (double p : r.psnrs) meanPsnr += p / r.psnrs.size();
  return {r.imageError, meanPsnr, bytes};
}

struct ShRow {
  int n = 0;
  ShFit fit = ShFit::Uls;
  ShStatistics stats{};
  StoredError stored[3]{};
};

struct ModelRow {
  std::string method;
  int clusters = 0, globalBases = 0;
  double costPerPixel = 0, medianNormRatio = 0, maxNormRatio = 0;
  StoredError stored[3]{};
};

std::string dB(double v) {
  return formatFixed(v, 2);
}

/// |T_p| of every row.
std::vector<double> rowNorms(const TransportReader& transport) {
  std::vector<double> rowNorm(transport.rows());
  streamRowBlocks(
      transport, rowsPerBlock(transport), [&](long long first, long long count, const float* rows) {
        for (long long r = 0; r < count; ++r) {
          double sum = 0;
          for (int j = 0; j < transport.rowLength(); ++j)
            sum +=
                double(rows[r * transport.rowLength() + j]) * rows[r * transport.rowLength() + j];
          rowNorm[first + r] = std::sqrt(sum);
        }
      });
  return rowNorm;
}

/// Each row's |u_p| / (|T_p| + |mean_c|), at most 1 with orthonormal bases.
std::vector<double> normToBoundRatios(const Model& exact, const std::vector<double>& rowNorm) {
  // Orthonormal V_g and W_c: |u_p| <= |g_p - mean_c| <= |T_p| + |mean_c|.
  std::vector<double> ratios;
  for (int k = 0; k < exact.clusters(); ++k) {
    const double meanNorm =
        Eigen::Map<const Eigen::VectorXf>(
            exact.means.data() + static_cast<size_t>(k) * exact.globalBases(), exact.globalBases())
            .norm();
    for (auto i = exact.rowOffsets[k]; i < exact.rowOffsets[k + 1]; ++i) {
      const long long r = i - exact.rowOffsets[k];
      double sum = 0;
      for (int b = 0; b < exact.ranks[k]; ++b) sum += std::pow(exact.coefficient(k, r, b), 2);
      const double bound = rowNorm[exact.clusterRows[i]] + meanNorm;
      if (bound > 0) ratios.push_back(std::sqrt(sum) / bound);
    }
  }
  return ratios;
}

/// Each method's model, its coefficient norms against their bound, and its
/// images with the coefficients stored at f32, f16 and i8.
std::vector<ModelRow> measureModels(const TransportReader& transport, const EvaluationData& data,
                                    const QuantizationOptions& a, const StudyLog& log) {
  std::vector<ModelRow> modelRows;
  const std::vector<double> rowNorm = rowNorms(transport);
  for (const auto& method : a.methods) {
    CompressOptions c;
    c.method = parseMethod(method);
    c.tolerance = a.tolerance;
    c.globalEnergy = a.globalEnergy;
    c.clusters = a.cpcaClusters;
    const Model exact = compressTransport(transport, c);
    ModelRow row{method, exact.clusters(), exact.globalBases(), exact.costPerPixel()};
    const std::vector<double> ratios = normToBoundRatios(exact, rowNorm);
    row.medianNormRatio = median(ratios);
    row.maxNormRatio = ratios.empty() ? 0 : *std::max_element(ratios.begin(), ratios.end());
    for (int s = 0; s < 3; ++s) {
      Model stored = exact;
      storeCoefficients(stored, kStorages[s]);
      ModelRelighter relighter(stored);
      row.stored[s] =
          measure(data, relighter.bytesPerFrame(),
                  [&](const LatticeLighting& l, float* rgb) { relighter.relight(l, rgb); });
    }
    log(concat(method, ": PSNR f32 ", dB(row.stored[0].psnr), " f16 ", dB(row.stored[1].psnr),
               " i8 ", dB(row.stored[2].psnr), " dB; |u|/(|T|+|mean|) max ",
               formatFixed(row.maxNormRatio, 3)));
    modelRows.push_back(row);
  }
  return modelRows;
}

/// [Lam06]'s fits at every order, each relit from its coefficients as stored
/// at f32, f16 and i8.
std::vector<ShRow> measureShFits(const TransportReader& transport, const EvaluationData& data,
                                 const QuantizationOptions& a, const StudyLog& log) {
  std::vector<ShRow> shRows;
  ShTransport sh(transport, *std::max_element(a.shOrders.begin(), a.shOrders.end()), a.shGroups);
  log(concat("SH: ", sh.groups(), " normal groups"));
  for (int n : a.shOrders)
    for (ShFit fit : {ShFit::Uls, ShFit::Cls, ShFit::Ceb}) {
      ShRow row{n, fit};
      const Stopwatch fitWatch;
      const ShCoefficients exact = sh.fit(n, fit);
      row.stats = sh.statistics(exact);
      row.stats.fitSeconds = fitWatch.seconds();
      for (int s = 0; s < 3; ++s) {
        ShCoefficients stored = exact;
        storeShCoefficients(stored, kStorages[s]);
        row.stored[s] =
            measure(data, sh.frameBytes(stored),
                    [&](const LatticeLighting& l, float* rgb) { sh.relight(stored, l, rgb); });
      }
      log(concat("SH n=", n, " ", shFitName(fit), ": PSNR f32 ", dB(row.stored[0].psnr), " f16 ",
                 dB(row.stored[1].psnr), " i8 ", dB(row.stored[2].psnr),
                 " dB; |c|/sqrt(E_c) median ", formatFixed(row.stats.medianNormToBound, 2), " max ",
                 formatFixed(row.stats.maxNormToBound, 1)));
      shRows.push_back(row);
    }
  return shRows;
}

/// sh.csv and models.csv in `outDir`; the same rows as JSON.
std::pair<nlohmann::json, nlohmann::json> writeQuantizationTables(
    const std::vector<ShRow>& shRows, const std::vector<ModelRow>& modelRows,
    const std::string& outDir) {
  // CSV, JSON and the summary's two tables.
  // Each table's own columns, then error, PSNR and bytes per storage.
  const auto withStored = [](std::vector<std::string> columns) {
    for (CoeffPrecision s : kStorages)
      for (const char* what : {"_rel_l2", "_psnr", "_bytes"})
        columns.push_back(coeffPrecisionName(s) + std::string(what));
    return columns;
  };
  Table shCsv(withStored({"n", "fit", "median_condition", "max_condition", "median_norm",
                          "max_norm", "median_norm_to_bound", "max_norm_to_bound", "fit_seconds"}));
  Table modelCsv(withStored({"method", "clusters", "global_bases", "cost_per_pixel",
                             "median_norm_to_bound", "max_norm_to_bound"}));
  const auto storedJson = [](const StoredError(&stored)[3]) {
    nlohmann::json j;
    for (int s = 0; s < 3; ++s)
      j[coeffPrecisionName(kStorages[s])] = {{"rel_l2", stored[s].error},
                                             {"psnr", finiteOrNull(stored[s].psnr)},
                                             {"bytes", stored[s].bytes}};
    return j;
  };
  const auto storedCells = [](std::vector<Table::Cell> cells, const StoredError(&stored)[3]) {
    for (const auto& s : stored) cells.insert(cells.end(), {s.error, s.psnr, s.bytes});
    return cells;
  };
  nlohmann::json shJson = nlohmann::json::array(), modelJson = nlohmann::json::array();
  for (const auto& r : shRows) {
    shCsv.add(storedCells({(long long)r.n, std::string(shFitName(r.fit)), r.stats.medianCondition,
                           r.stats.maxCondition, r.stats.medianNorm, r.stats.maxNorm,
                           r.stats.medianNormToBound, r.stats.maxNormToBound, r.stats.fitSeconds},
                          r.stored));
    shJson.push_back({{"n", r.n},
                      {"fit", shFitName(r.fit)},
                      {"median_condition", finiteOrNull(r.stats.medianCondition)},
                      {"max_condition", finiteOrNull(r.stats.maxCondition)},
                      {"median_norm_to_bound", r.stats.medianNormToBound},
                      {"max_norm_to_bound", r.stats.maxNormToBound},
                      {"stored", storedJson(r.stored)}});
  }
  for (const auto& r : modelRows) {
    modelCsv.add(storedCells({r.method, (long long)r.clusters, (long long)r.globalBases,
                              r.costPerPixel, r.medianNormRatio, r.maxNormRatio},
                             r.stored));
    modelJson.push_back({{"method", r.method},
                         {"clusters", r.clusters},
                         {"global_bases", r.globalBases},
                         {"cost_per_pixel", r.costPerPixel},
                         {"median_norm_to_bound", r.medianNormRatio},
                         {"max_norm_to_bound", r.maxNormRatio},
                         {"stored", storedJson(r.stored)}});
  }
  shCsv.writeCsv((fs::path(outDir) / "sh.csv").string());
  modelCsv.writeCsv((fs::path(outDir) / "models.csv").string());

  return {shJson, modelJson};
}

/// summary.md's text: the two tables in words.
std::string quantizationSummary(const TransportReader& transport, const EvaluationData& data,
                                const QuantizationOptions& a, const std::vector<ShRow>& shRows,
                                const std::vector<ModelRow>& modelRows) {
  std::ostringstream md;
  md << "# Coefficient quantization: " << fs::path(transport.path()).filename().string() << "\n\n"
     << "PSNR (dB) of the relit images against the dense relight, mean over " << data.envs.size()
     << " maps (";
  for (size_t k = 0; k < data.envs.size(); ++k) md << (k ? ", " : "") << data.envs[k];
  md << "); relative L2 of the raw reconstruction (before the clamp at zero written frames "
        "get) aggregated as RMS over the maps. i8 quantizes each coefficient map "
        "(SH: the same coefficient of every pixel; models: each cluster's coefficients) "
        "uniformly to its largest magnitude / 127.\n\n"
     << "## Spherical harmonics (Lam, Leung and Wong 2006, Table III)\n\n"
     << "Rows grouped by normal on a 6x" << a.shGroups << "x" << a.shGroups
     << " cube; each group's Gram matrix over its support (hemisphere plus every lit texel). "
        "‖c‖/√E_c is the coefficient norm over the bound of eq. 17.\n\n"
     << "| n | fit | cond (median) | cond (max) | ‖c‖/√E_c median | max | f32 dB | f16 dB "
        "| i8 dB | f32 err | i8 err |\n|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : shRows)
    md << "| " << r.n << " | " << shFitName(r.fit) << " | "
       << formatFixed(r.stats.medianCondition, 0) << " | " << formatFixed(r.stats.maxCondition, 0)
       << " | " << formatFixed(r.stats.medianNormToBound, 2) << " | "
       << formatFixed(r.stats.maxNormToBound, 1) << " | " << dB(r.stored[0].psnr) << " | "
       << dB(r.stored[1].psnr) << " | " << dB(r.stored[2].psnr) << " | "
       << formatFixed(100 * r.stored[0].error, 2) << "% | "
       << formatFixed(100 * r.stored[2].error, 2) << "% |\n";
  md << "\n## Our models\n\n"
     << "Tolerance " << a.tolerance << ", global energy " << a.globalEnergy << ", CPCA with "
     << a.cpcaClusters
     << " clusters. ‖u‖/(‖T‖+‖m‖): a pixel's coefficient norm over its transport row's norm plus "
        "its cluster mean's (at most 1 with orthonormal bases; ‖u‖/‖T‖ without a mean). i8 keeps "
        "one "
        "scale per cluster basis.\n\n"
     << "| method | clusters | N | cost/pixel | ‖u‖/(‖T‖+‖m‖) median | max | f32 dB | f16 dB | i8 "
        "dB "
        "| f32 err | f16 err | i8 err | i8 MB |\n"
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : modelRows)
    md << "| " << r.method << " | " << r.clusters << " | " << r.globalBases << " | "
       << formatFixed(r.costPerPixel, 0) << " | " << formatFixed(r.medianNormRatio, 3) << " | "
       << formatFixed(r.maxNormRatio, 3) << " | " << dB(r.stored[0].psnr) << " | "
       << dB(r.stored[1].psnr) << " | " << dB(r.stored[2].psnr) << " | "
       << formatFixed(100 * r.stored[0].error, 3) << "% | "
       << formatFixed(100 * r.stored[1].error, 3) << "% | "
       << formatFixed(100 * r.stored[2].error, 3) << "% | "
       << formatFixed(r.stored[2].bytes / 1e6, 1) << " |\n";
  return md.str();
}

}  // namespace

StudyOutput runQuantizationStudy(const TransportReader& transport, const QuantizationOptions& a,
                                 const std::string& outDir) {
  for (int n : a.shOrders) shBandsOf(n, "SH orders");
  for (const auto& m : a.methods) parseMethod(m);
  const Stopwatch watch;
  const StudyLog log = [&](const std::string& text) {
    if (a.log) a.log(text);
  };
  createOutputDirectory(outDir);
  const EvaluationData data = loadEvaluationData(transport, a.envs);
  const std::vector<ShRow> shRows =
      a.noSh ? std::vector<ShRow>{} : measureShFits(transport, data, a, log);
  const std::vector<ModelRow> modelRows =
      a.noModels ? std::vector<ModelRow>{} : measureModels(transport, data, a, log);
  const auto [shJson, modelJson] = writeQuantizationTables(shRows, modelRows, outDir);
  const std::string md = quantizationSummary(transport, data, a, shRows, modelRows) + "\n" +
                         formatFixed(watch.seconds(), 0) + " s.\n";
  writeTextFile((fs::path(outDir) / "summary.md").string(), md);
  return {{{"input", transport.path()}, {"envs", data.envs}, {"sh", shJson}, {"models", modelJson}},
          md};
}

}  // namespace acpca
