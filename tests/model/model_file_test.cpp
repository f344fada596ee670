// The model file read and written by the model library alone (no compressor
// linked): a hand-made two-cluster model at every coefficient precision
// round-trips exactly, and its reference relight is the definition's sum.
#include "model/model_file.h"

#include <gtest/gtest.h>

#include <random>

#include "model/model_reference.h"
#include "tests/model_support.h"
#include "tests/temp_dir.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

/// Two clusters over the grid2d fixture's rows (first half rank 2, second
/// half rank 1), N = 3 global bases, with means, seeded values.
Model handMadeModel(CoeffPrecision precision) {
  Model m;
  m.geometry = TransportReader(test::fixture("grid2d")).header();
  m.method = "adaptive-quad";
  m.settings = R"({"made":"by hand"})";
  const int l = m.geometry.latticeSize(), n = 3;
  const long long rows = m.rows(), half = rows / 2;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1, 1);
  m.globalBasis = Eigen::MatrixXf::NullaryExpr(l, n, [&] { return u(rng); });
  m.hasMean = true;
  m.precision = precision;
  m.ranks = {2, 1};
  m.rowOffsets = {0, half, rows};
  for (long long r = 0; r < rows; ++r) m.clusterRows.push_back(static_cast<std::int32_t>(r));
  m.basisOffsets = {0, 2 * n, 3 * n};
  for (int i = 0; i < 3 * n; ++i) m.bases.push_back(u(rng));
  for (int i = 0; i < 2 * n; ++i) m.means.push_back(u(rng));
  m.coefficientOffsets = {0, 2 * half, 2 * half + (rows - half)};
  const long long coefficients = m.coefficientOffsets.back();
  for (long long i = 0; i < coefficients; ++i) {
    if (precision == CoeffPrecision::F32) m.coeffF32.push_back(u(rng));
    if (precision == CoeffPrecision::I8)
      m.coeffI8.push_back(static_cast<std::int8_t>(127 * u(rng)));
  }
  // A scale per basis (docs/formats.md): 1 unless the coefficients are i8.
  m.coeffScale = precision == CoeffPrecision::I8 ? std::vector<float>{0.01f, 0.02f, 0.03f}
                                                 : std::vector<float>(3, 1.0f);
  return m;
}

TEST(ModelFile, AHandMadeModelRoundTripsExactlyAtEveryPrecision) {
  for (CoeffPrecision precision : {CoeffPrecision::F32, CoeffPrecision::I8}) {
    const Model m = handMadeModel(precision);
    test::TempDir dir;
    const std::string path = dir.file("m.h5");
    writeModel(m, path);
    ASSERT_TRUE(isModelFile(path));
    test::expectSameModelArrays(readModel(path), m);
  }
}

TEST(ModelFile, TheReferenceRelightIsTheDefinitionsSum) {
  // Relit value of row p in cluster i: albedo_p (u_p . W_i^T V_g^T L + mu_i . V_g^T L).
  const Model m = handMadeModel(CoeffPrecision::I8);
  const int l = m.geometry.latticeSize(), n = m.globalBases();
  std::vector<double> lighting(3 * static_cast<size_t>(l));
  for (size_t j = 0; j < lighting.size(); ++j) lighting[j] = 0.5 + 0.25 * std::sin(double(j));
  const std::vector<float> relit = relightModelReference(m, {lighting})[0];
  ASSERT_EQ(relit.size(), 3 * static_cast<size_t>(m.rows()));
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd light(l);
    for (int j = 0; j < l; ++j) light[j] = lighting[3 * j + c];
    const Eigen::VectorXd projected = m.globalBasis.cast<double>().transpose() * light;
    for (int i = 0; i < m.clusters(); ++i)
      for (long long r = 0; r < m.rowOffsets[i + 1] - m.rowOffsets[i]; ++r) {
        double value = 0;
        for (int k = 0; k < n; ++k) {
          double basisDot = m.means[i * n + k];
          for (int b = 0; b < m.ranks[i]; ++b)
            basisDot += m.coefficient(i, r, b) * m.bases[m.basisOffsets[i] + b * n + k];
          value += basisDot * projected[k];
        }
        const long long row = m.clusterRows[m.rowOffsets[i] + r];
        EXPECT_NEAR(relit[3 * row + c], m.geometry.albedo[3 * row + c] * value,
                    1e-4 * (1 + std::abs(value)))
            << "row " << row << " channel " << c;
      }
  }
}

}  // namespace
}  // namespace acpca
