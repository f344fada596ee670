#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <filesystem>
#include <limits>
#include <random>

#include "cluster/compress.h"
#include "cluster/global_basis.h"
#include "cluster/rank_allocation.h"
#include "model/cost_model.h"
#include "model/model_file.h"
#include "model/model_reference.h"
#include "model/model_summary.h"
#include "tests/model_support.h"
#include "tests/test_support.h"
#include "transport/hdf5_handles.h"

namespace acpca {
namespace {

TEST(CostModel, MatchesHandComputedValues) {
  EXPECT_EQ(clusterCost(3, 10, 20), 90);  // 3 (10 + 20)
  // d = (1 - mu) n p + (1 - r mu) n N with mu 0.6, r 2, n 10, p 100, N 50:
  // 0.4 * 1000 + (1 - 1.2) * 500 = 400 - 100 = 300.
  EXPECT_NEAR(subdivisionMetric(0.6, 2, 10, 100, 50), 300, 1e-9);
  EXPECT_LT(subdivisionMetric(0.9, 4, 10, 10, 500), 0);  // small patches do not split
  EXPECT_NEAR(optimalPatchSize(0.5, 4, 100), 100.0 * (2 - 1) / 0.5, 1e-9);  // eq. 27
}

/// Synthetic global coefficients on a w x h image, every pixel occupied.
struct Synthetic {
  RowMatrixF g;
  std::vector<std::int32_t> pixels;
  ImageSize size;
  ClusterInput input(double tolerance = 0.999, bool mean = false) const {
    return {&g, &pixels, size, tolerance, mean};
  }
};

Synthetic synthetic(int w, int h, int n) {
  Synthetic s;
  s.size = {w, h};
  s.g = RowMatrixF::Zero(w * h, n);
  for (int p = 0; p < w * h; ++p) s.pixels.push_back(p);
  return s;
}

TEST(AdaptiveQuad, SplitsOnlyTheRichHalf) {
  const int w = 32, h = 16, n = 96;
  Synthetic s = synthetic(w, h, n);
  std::mt19937 rng(3);
  std::normal_distribution<float> normal;
  Eigen::VectorXf common(n);
  for (auto& v : common) v = normal(rng);
  // Right half: every 4x4 tile has its own direction, so the half has rank 16
  // while each tile is rank 1 (locally low-dimensional, as transport is).
  std::vector<Eigen::VectorXf> tiles(16, Eigen::VectorXf(n));
  for (auto& t : tiles)
    for (auto& v : t) v = normal(rng);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      auto row = s.g.row(y * w + x);
      if (x < w / 2)
        row = (1 + 0.1f * x) * common.transpose();  // rank 1
      else
        row = (1 + 0.05f * y) * tiles[(y / 4) * 4 + (x - w / 2) / 4].transpose();
    }
  const Partition p = adaptiveQuadTree(s.input(0.99), {16, 2, false});
  int leftClusters = 0, rightClusters = 0;
  for (const auto& c : p) {
    const bool left = c.front() % w < w / 2;
    for (int r : c) ASSERT_EQ(r % w < w / 2, left) << "a cluster spans both halves";
    (left ? leftClusters : rightClusters)++;
  }
  EXPECT_EQ(leftClusters, 1);
  EXPECT_GT(rightClusters, 4);
}

TEST(Cpca, RecoversRowsDrawnFromKnownSubspaces) {
  const int k = 4, perCluster = 150, n = 40, dim = 3;
  Synthetic s = synthetic(k * perCluster, 1, n);
  std::mt19937 rng(9);
  std::normal_distribution<float> normal;
  std::vector<int> truth;
  for (int c = 0; c < k; ++c) {
    Eigen::MatrixXf basis(dim, n), offset(1, n);
    for (auto& v : basis.reshaped()) v = normal(rng);
    for (auto& v : offset.reshaped()) v = 3 * normal(rng);
    for (int i = 0; i < perCluster; ++i) {
      Eigen::RowVectorXf coeffs(dim);
      for (auto& v : coeffs) v = normal(rng);
      s.g.row(c * perCluster + i) = offset + coeffs * basis;
      truth.push_back(c);
    }
  }
  std::vector<int> all(k * perCluster);
  std::iota(all.begin(), all.end(), 0);
  CpcaOptions o;
  o.clusters = k;
  o.iterationRank = dim;
  const Partition p = cpca(s.input(0.999, true), all, o);
  ASSERT_EQ(p.size(), size_t(k));
  int agreeing = 0;
  for (const auto& c : p) {
    std::vector<int> votes(k, 0);
    for (int r : c) ++votes[truth[r]];
    agreeing += *std::max_element(votes.begin(), votes.end());
  }
  EXPECT_GE(agreeing, 0.95 * k * perCluster);
}

TEST(AdaptiveBinary, SplitsInterleavedSubspacesApartAndStopsNearPureClusters) {
  // Four groups of rows, each an offset plus multiples of one direction (rank 1
  // with a mean), interleaved pixel by pixel so no image block separates them.
  // The whole needs about 7 bases; each group 1 plus its mean, and halving a
  // group cannot lower that: splitting must separate the groups and then stop.
  const int groups = 4, perGroup = 300, n = 64;
  Synthetic s = synthetic(groups * perGroup, 1, n);
  std::mt19937 rng(4);
  std::normal_distribution<float> normal;
  std::vector<Eigen::RowVectorXf> offsets(groups, Eigen::RowVectorXf(n)),
      directions(groups, Eigen::RowVectorXf(n));
  for (int c = 0; c < groups; ++c)
    for (int k = 0; k < n; ++k) offsets[c][k] = 3 * normal(rng), directions[c][k] = normal(rng);
  for (int r = 0; r < groups * perGroup; ++r)
    s.g.row(r) = offsets[r % groups] + normal(rng) * directions[r % groups];
  ClusterInput in = s.input(0.999, true);
  in.clusteringDims = 8;
  BinaryOptions o;
  o.initialClusters = 1;
  // Assignment by reconstruction error separates groups only if a cluster's
  // iteration bases cannot hold two of them, as with transport, whose clusters
  // need far more than 8 bases: one basis here, as the groups have rank 1.
  o.split.iterationRank = 1;
  const double pure = groups * costOf(in, std::vector<int>(perGroup), 1);  // 4 x 2 (300 + 64)
  // Clusters of more than 200 rows judged on the 8 leading coefficients and the
  // rest exactly; then every cluster exactly.
  for (long long exactRows : {200LL, 100000LL}) {
    o.exactTestRows = exactRows;
    const Partition p = adaptiveBinary(in, o);
    EXPECT_GE(p.size(), size_t(groups)) << "exact test below " << exactRows << " rows";
    EXPECT_LE(p.size(), size_t(2 * groups));
    double cost = 0;
    size_t covered = 0;
    for (const auto& cluster : p) {
      for (int r : cluster) EXPECT_EQ(r % groups, cluster.front() % groups) << "a mixed cluster";
      EXPECT_EQ(rankOf(in, cluster), cluster.size() > 1 ? 1 : 0);
      cost += costOf(in, cluster, rankOf(in, cluster));
      covered += cluster.size();
    }
    EXPECT_EQ(covered, size_t(groups * perGroup));
    // A stray row or two split off by CPCA's local optimum costs a little more
    // than the four pure clusters; the whole as one cluster costs 3.3x as much.
    EXPECT_LE(cost, 1.1 * pure);
    const std::vector<int> whole = singleCluster(in)[0];
    EXPECT_GT(costOf(in, whole, rankOf(in, whole)), 3 * pure);
  }
}

TEST(Partitions, DegenerateInputsGiveSensibleModels) {
  Synthetic zero = synthetic(4, 4, 8);  // all-zero rows
  EXPECT_EQ(rankOf(zero.input(), singleCluster(zero.input())[0]), 0);
  Synthetic one = synthetic(1, 1, 8);  // a single pixel
  one.g.row(0).setOnes();
  EXPECT_EQ(adaptiveQuadTree(one.input(), {64, 2, false}).size(), 1u);
  std::vector<int> single{0};
  EXPECT_EQ(cpca(one.input(), single, {}).size(), 1u);
  Synthetic dup = synthetic(8, 1, 8);  // duplicate rows: rank 1
  for (int r = 0; r < 8; ++r) dup.g.row(r).setConstant(2);
  EXPECT_EQ(rankOf(dup.input(1.0), singleCluster(dup.input())[0]), 1);
  std::vector<int> all(8);
  std::iota(all.begin(), all.end(), 0);
  CpcaOptions many;
  many.clusters = 20;  // more clusters than rows
  const Partition p = cpca(dup.input(), all, many);
  size_t covered = 0;
  for (const auto& c : p) covered += c.size();
  EXPECT_EQ(covered, 8u);
}

TEST(Compress, AnImageThatIsAllBackgroundGivesAnEmptyModel) {
  test::TempDir dir;
  TransportHeader empty;  // a camera that sees nothing: no occupied pixel
  empty.camera.size = {8, 8};
  empty.cubemapResolution = 4;
  TransportWriter(dir.file("t.h5"), empty).finish();
  const TransportReader t(dir.file("t.h5"));
  ASSERT_EQ(t.rows(), 0);
  for (Method method : {Method::Global, Method::Block, Method::Cpca, Method::AdaptiveQuad,
                        Method::AdaptiveBinary}) {
    CompressOptions c;
    c.method = method;
    Model m = compressTransport(t, c);
    EXPECT_EQ(m.clusters(), 0) << methodName(method);
    EXPECT_EQ(m.totalCost(), 0);
    EXPECT_EQ(m.transportError, 0);
    writeModel(m, dir.file("m.h5"));
    EXPECT_EQ(readModel(dir.file("m.h5")).clusters(), 0);
  }
}

TEST(RankAllocation, SpendsTheBudgetWhereItBuysTheMost) {
  const std::vector<Eigen::VectorXd> spectra{Eigen::Vector2d(10, 1), Eigen::Vector2d(5, 4)};
  const std::vector<long long> sizes{10, 10};
  // Per unit cost: 1.0, 0.1 and 0.5, 0.4: take 10, then 5, then 4.
  EXPECT_EQ(allocateRanks(spectra, sizes, 0, 20), (std::vector<int>{0, 0}));
  EXPECT_EQ(allocateRanks(spectra, sizes, 0, 6), (std::vector<int>{1, 1}));
  EXPECT_EQ(allocateRanks(spectra, sizes, 0, 1.5), (std::vector<int>{1, 2}));
  EXPECT_EQ(allocateRanks(spectra, sizes, 0, 0), (std::vector<int>{2, 2}));
  // A large cluster pays more per basis: the small one gets the basis first.
  EXPECT_EQ(allocateRanks({Eigen::Vector2d(6, 0), Eigen::Vector2d(5, 0)}, {100, 1}, 0, 6),
            (std::vector<int>{0, 1}));
}

class CompressPlant : public test::SmallPlantSuite {};

TEST_F(CompressPlant, ErrorFallsAsTheToleranceTightensAndQuantizationStaysBounded) {
  const TransportReader t(path());
  double previous = 1;
  for (double tol : {0.9, 0.99, 0.999}) {
    CompressOptions o;
    o.tolerance = tol;
    o.block = 8;
    const Model m = compressTransport(t, o);
    EXPECT_LT(m.transportError, previous + 1e-9);
    previous = m.transportError;
  }
  CompressOptions o;
  o.method = Method::Block;
  const Model f32 = compressTransport(t, o);
  o.coeffs = CoeffPrecision::F16;
  const Model f16 = compressTransport(t, o);
  o.coeffs = CoeffPrecision::I8;
  const Model i8 = compressTransport(t, o);
  // Half keeps 11 significant bits; 8 bits with a per-cluster scale at most
  // half a step (max|u| / 254) per coefficient: both add little to the error.
  EXPECT_LT(f16.transportError, f32.transportError * 1.001 + 1e-6);
  EXPECT_LT(i8.transportError, f32.transportError + 0.05);
  EXPECT_GE(i8.transportError, f32.transportError - 1e-12);
}

TEST_F(CompressPlant, RankAllocationHonoursTheOverallBudget) {
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveQuad;
  o.block = 16;
  o.tolerance = 0.99;
  const Model perCluster = compressTransport(t, o);
  o.allocateRanks = true;
  const Model allocated = compressTransport(t, o);
  // Global residual (1 - kept) plus at most 1% of the clusters' energy, which is
  // at most 1% of the whole.
  const double bound =
      std::sqrt((1 - allocated.globalEnergyKept) + 0.01 * allocated.globalEnergyKept);
  EXPECT_LE(allocated.transportError, bound * (1 + 1e-9));
  EXPECT_LE(perCluster.transportError, bound * (1 + 1e-9));
  EXPECT_GT(allocated.totalCost(), 0);
}

TEST_F(CompressPlant, SameModelForAnyThreadCountAndSeedAndTheFileRoundTrips) {
  test::TempDir dir;
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveBinary;
  o.clusters = 3;
  Model one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = compressTransport(t, o);
  }
  two = compressTransport(t, o);
  EXPECT_EQ(one.clusterRows, two.clusterRows);
  EXPECT_EQ(one.ranks, two.ranks);
  EXPECT_EQ(one.bases, two.bases);
  EXPECT_EQ(one.coeffF32, two.coeffF32);
  one.method = "adaptive-binary";
  writeModel(one, dir.file("m.h5"));
  EXPECT_TRUE(isModelFile(dir.file("m.h5")));
  EXPECT_FALSE(isModelFile(path()));
  const Model back = readModel(dir.file("m.h5"));
  EXPECT_EQ(back.bases, one.bases);
  EXPECT_EQ(back.coeffF32, one.coeffF32);
  EXPECT_EQ(back.clusterRows, one.clusterRows);
  EXPECT_NEAR(back.totalCost(), one.totalCost(), 1e-9);
  // Version 5 keeps what the labels need: each pixel's normal and object.
  EXPECT_EQ(back.geometry.normals, one.geometry.normals);
  EXPECT_EQ(back.geometry.objects, one.geometry.objects);
  EXPECT_EQ(back.geometry.objectNames, one.geometry.objectNames);
  EXPECT_TRUE(back.geometry.hasNormals() && back.geometry.hasObjects());
  EXPECT_THROW(readModel(path()), UserError);

  // Every stored value finite, but a basis value times a coefficient
  // overflows a float: the file is refused, not relit to infinity.
  Model huge = one;
  huge.bases[0] = 1e30f;
  huge.coeffF32[0] = 1e30f;
  writeModel(huge, dir.file("huge.h5"));
  try {
    readModel(dir.file("huge.h5"));
    ADD_FAILURE() << "a model whose products overflow was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

/// Fills a float dataset of the file with NaN (its values only: shapes and
/// attributes stay as they were).
void poisonDataset(const std::string& path, const char* name) {
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0);
  h5::Handle data(H5Dopen2(file.get(), name, H5P_DEFAULT), H5Dclose);
  ASSERT_GE(data.get(), 0) << name;
  h5::Handle space(H5Dget_space(data.get()), H5Sclose);
  std::vector<float> nan(static_cast<size_t>(H5Sget_simple_extent_npoints(space.get())),
                         std::numeric_limits<float>::quiet_NaN());
  ASSERT_GE(H5Dwrite(data.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, nan.data()), 0);
}

TEST_F(CompressPlant, AdaptiveBinaryOnFourThreadsSplitsAsOnOne) {
  // More threads than CI's two cores: the splits' eigenproblems run side by
  // side on four (the sanitizer stage runs this too), and the model is the
  // one-thread model bit for bit.
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveBinary;
  o.clusters = 6;
  Model one, four;
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = compressTransport(t, o);
  }
  {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 4);
    tbb::task_arena arena(4);
    arena.execute([&] { four = compressTransport(t, o); });
  }
  EXPECT_GT(one.clusters(), 6);
  EXPECT_EQ(one.clusterRows, four.clusterRows);
  EXPECT_EQ(one.ranks, four.ranks);
  EXPECT_EQ(one.bases, four.bases);
  EXPECT_EQ(one.coeffF32, four.coeffF32);
}

TEST_F(CompressPlant, ASummaryGivesTheWholeModelsFiguresWithoutReadingItsArrays) {
  test::TempDir dir;
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveBinary;
  o.clusters = 4;
  Model model = compressTransport(t, o);
  model.method = "adaptive-binary";
  const std::string file = dir.file("m.h5");
  writeModel(model, file);
  const Model whole = readModel(file);
  const auto expectSameFigures = [&](const ModelSummary& s) {
    EXPECT_EQ(s.pixels.rows, whole.rows());
    EXPECT_EQ(s.pixels.normals, whole.geometry.hasNormals());
    EXPECT_EQ(s.pixels.positions, whole.geometry.hasPositions());
    EXPECT_EQ(s.pixels.objects, whole.geometry.hasObjects());
    EXPECT_EQ(s.geometry.objectNames, whole.geometry.objectNames);
    EXPECT_EQ(s.geometry.camera.size.pixels(), whole.geometry.camera.size.pixels());
    EXPECT_EQ(s.method, whole.method);
    EXPECT_EQ(s.globalBases, whole.globalBases());
    EXPECT_EQ(s.clusters(), whole.clusters());
    EXPECT_EQ(s.ranks, whole.ranks);
    EXPECT_EQ(s.rowOffsets, whole.rowOffsets);
    EXPECT_EQ(s.totalCost(), whole.totalCost());  // the same sums in the same order
    EXPECT_EQ(s.costPerPixel(), whole.costPerPixel());
    EXPECT_EQ(s.frameBytes(), whole.frameBytes());
    EXPECT_EQ(s.transportError, whole.transportError);
    EXPECT_EQ(s.fileBytes, static_cast<long long>(std::filesystem::file_size(file)));
  };
  expectSameFigures(readModelSummary(file));
  // Its arrays' values spoilt, the model is refused whole and summarized alike.
  for (const char* array : {"coefficients", "bases", "albedo", "normal", "position"})
    poisonDataset(file, array);
  EXPECT_THROW(readModel(file), UserError);
  expectSameFigures(readModelSummary(file));
}

TEST_F(CompressPlant, AModelWrittenInPiecesReadsAsTheWholeOne) {
  // The streamed build appends each tile's clusters as it finishes them: the
  // file must read back as the same model as one written at once.
  test::TempDir dir;
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveQuad;
  o.block = 16;
  o.coeffs = CoeffPrecision::I8;
  o.bases = CoeffPrecision::F16;
  Model whole = compressTransport(t, o);
  whole.method = "adaptive-quad";
  ASSERT_GT(whole.clusters(), 3);
  // The clusters cut in three pieces, each with offsets from 0.
  const auto piece = [&](int first, int last) {
    Model m;
    m.hasMean = whole.hasMean;
    m.precision = whole.precision;
    m.basisPrecision = whole.basisPrecision;
    const int n = whole.globalBases();
    m.rowOffsets = {0}, m.basisOffsets = {0}, m.coefficientOffsets = {0};
    for (int c = first; c < last; ++c) {
      const long long r0 = whole.rowOffsets[c], r1 = whole.rowOffsets[c + 1];
      m.clusterRows.insert(m.clusterRows.end(), whole.clusterRows.begin() + r0,
                           whole.clusterRows.begin() + r1);
      m.rowOffsets.push_back(m.clusterRows.size());
      m.ranks.push_back(whole.ranks[c]);
      m.bases.insert(m.bases.end(), whole.bases.begin() + whole.basisOffsets[c],
                     whole.bases.begin() + whole.basisOffsets[c + 1]);
      m.basisOffsets.push_back(m.bases.size());
      m.means.insert(m.means.end(), whole.means.begin() + c * n, whole.means.begin() + (c + 1) * n);
      m.coeffI8.insert(m.coeffI8.end(), whole.coeffI8.begin() + whole.coefficientOffsets[c],
                       whole.coeffI8.begin() + whole.coefficientOffsets[c + 1]);
      m.coefficientOffsets.push_back(m.coeffI8.size());
      m.coeffScale.insert(m.coeffScale.end(), whole.coeffScale.begin() + whole.firstBasisIndex(c),
                          whole.coeffScale.begin() + whole.firstBasisIndex(c) + whole.ranks[c]);
    }
    return m;
  };
  const int c = whole.clusters();
  {
    ModelFileWriter writer(dir.file("pieces.h5"), whole, ModelSizes::of(whole));
    for (const auto& [first, last] : {std::pair{0, 1}, std::pair{1, c / 2}, std::pair{c / 2, c}})
      writer.append(piece(first, last));
    EXPECT_EQ(writer.clustersWritten(), c);
    EXPECT_DOUBLE_EQ(writer.totalCost(), whole.totalCost());
    writer.finish(whole);
  }
  const Model back = readModel(dir.file("pieces.h5"));
  test::expectSameModelArrays(back, whole);
  // A writer that never finishes leaves nothing behind.
  { ModelFileWriter unfinished(dir.file("never.h5"), whole, ModelSizes::of(whole)); }
  EXPECT_FALSE(std::filesystem::exists(dir.file("never.h5")));
}

TEST(GlobalBasis, RowsTheSampleNeverSeesStillCountAsMissedEnergy) {
  // The basis lives on the directions its sample sees; a row with energy on
  // others (seen by rows outside the sample) must report that energy as
  // missed, or the transport error would be too small.
  const int l = 6;
  Eigen::MatrixXd sample = Eigen::MatrixXd::Zero(40, l);
  for (int r = 0; r < 40; ++r) sample(r, 0) = 1 + r, sample(r, 1) = 0.5 * r;
  const GlobalBasis basis = basisFromSample(sample, sample, {1.0, 40, 1});
  EXPECT_EQ(basis.active, (std::vector<int>{0, 1}));
  const float row[l] = {3, 1, 0, 2, 0, 0};  // direction 3: unseen by the sample
  for (double keep : {1.0, 0.5}) {          // the residual formed, or |t|^2 - |g|^2
    GlobalBasis b = basis;
    b.heldOutEnergyKept = keep;
    const GlobalProjection g = BasisProjector(b, l, l).project(row, 1);
    EXPECT_NEAR(g.rowEnergy[0], 14, 1e-9);
    const double inBasis = g.coefficients.row(0).cast<double>().squaredNorm();
    EXPECT_NEAR(g.residualEnergy[0], 14 - inBasis, 1e-5) << keep;
    EXPECT_GE(g.residualEnergy[0], 4 - 1e-5) << "direction 3's energy is missed";
  }
}

TEST(GlobalProjection, SkippingZeroRunsGivesTheFullProduct) {
  // The projection multiplies each group of rows without the lattice runs that
  // are zero in all of them; the result must be T V_g itself, for one row per
  // pixel and for R, G and B rows, and the plant's rows must have such runs.
  for (const char* name : {"small-plant", "bounced-plant"}) {
    const TransportReader t(test::fixture(name));
    const GlobalBasis basis = computeGlobalBasis(t, {0.999, 16384, 1});
    const GlobalProjection g = projectOntoBasis(t, basis);
    const int l = t.rowLength();
    std::vector<float> rows(static_cast<size_t>(t.rows()) * l);
    t.readRows(0, t.rows(), rows.data());
    const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
        dense(rows.data(), t.rows(), l);
    const Eigen::MatrixXd exact = dense.cast<double>() * basis.basis.cast<double>();
    ASSERT_EQ(g.coefficients.rows(), exact.rows());
    double worst = 0;
    for (Eigen::Index r = 0; r < exact.rows(); ++r) {
      const double scale = dense.row(r).cast<double>().norm() + 1e-30;
      worst = std::max(worst, (g.coefficients.row(r).cast<double>() - exact.row(r)).norm() / scale);
    }
    EXPECT_LT(worst, 1e-5) << name;
    const int half = t.latticeSize() / 12;  // half a face: the product's run
    long long zeroRuns = 0;
    for (Eigen::Index r = 0; r < dense.rows(); ++r)
      for (int j = 0; j + half <= l; j += half) zeroRuns += dense.row(r).segment(j, half).isZero(0);
    EXPECT_GT(zeroRuns, dense.rows() * (l / half) / 5) << name << ": too few zero runs to test";
  }
}

TEST(GlobalBasis, TheFileBasisReadsExactlyTheSampledRows) {
  // The file pass reads only the sampled and held-out rows (runs of them):
  // gathering the same rows from the whole transport must give the same basis.
  const TransportReader t(test::fixture("small-plant"));
  const GlobalBasisOptions options{0.999, 300, 7};
  const BasisSample chosen = chooseBasisSample(t.rows(), options);
  ASSERT_LT(static_cast<long long>(chosen.rows.size()), t.rows());
  const int l = t.rowLength();
  std::vector<float> all(static_cast<size_t>(t.rows()) * l);
  t.readRows(0, t.rows(), all.data());
  const auto gather = [&](const std::vector<long long>& list) {
    Eigen::MatrixXd m(static_cast<Eigen::Index>(list.size()), l);
    for (size_t i = 0; i < list.size(); ++i)
      for (int j = 0; j < l; ++j) m(static_cast<Eigen::Index>(i), j) = all[list[i] * l + j];
    return m;
  };
  const GlobalBasis expected =
      basisFromSample(gather(chosen.rows), gather(chosen.heldOut), options);
  const GlobalBasis fromFile = computeGlobalBasis(t, options);
  ASSERT_GT(fromFile.globalBases(), 0);
  EXPECT_EQ(fromFile.basis, expected.basis);
  EXPECT_EQ(fromFile.active, expected.active);
  EXPECT_EQ(fromFile.heldOutEnergyKept, expected.heldOutEnergyKept);
  EXPECT_GT(fromFile.heldOutEnergyKept, 0.9);
  EXPECT_LE(fromFile.heldOutEnergyKept, 1.0 + 1e-12);
}

TEST(CompressBouncedPlant, RgbRowsModelRoundTripsWithItsLayout) {
  test::TempDir dir;
  const TransportReader t(test::fixture("bounced-plant"));
  CompressOptions o;
  o.method = Method::AdaptiveQuad;
  const Model m = compressTransport(t, o);
  ASSERT_EQ(m.geometry.channels, 3);
  ASSERT_EQ(m.globalBasis.rows(), 3 * t.latticeSize());
  writeModel(m, dir.file("m.h5"));
  const Model back = readModel(dir.file("m.h5"));
  EXPECT_EQ(back.geometry.channels, 3);
  EXPECT_EQ(back.globalBasis, m.globalBasis);
  EXPECT_EQ(back.coeffF32, m.coeffF32);
}

}  // namespace
}  // namespace acpca
