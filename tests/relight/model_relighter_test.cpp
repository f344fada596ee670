// The fast relighter against the plain reference loops and the dense ground
// truth; quantization bounds; rank limits; thread-count independence.
#include "relight/model_relighter.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

#include <Eigen/Core>
#include <cmath>
#include <random>

#include "cluster/compress.h"
#include "cluster/global_basis.h"
#include "cluster/model_fit.h"
#include "cluster/partition.h"
#include "cluster/quantization.h"
#include "core/half.h"
#include "core/statistics.h"
#include "lighting/lighting.h"
#include "model/model_file.h"
#include "model/model_reference.h"
#include "relight/dense_relight.h"
#include "relight/image_composer.h"
#include "relight/local_relight.h"
#include "relight/relight_kernels.h"
#include "tests/lighting_support.h"
#include "tests/model_support.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::appendCoefficients;
using test::bandedModel;

/// Largest |a - b| over the image, relative to the largest |b|.
double maxRelativeDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double diff = 0, scale = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(double(a[i]) - b[i]));
    scale = std::max(scale, std::abs(double(b[i])));
  }
  return scale > 0 ? diff / scale : diff;
}

/// A model with every awkward shape, filled with random numbers: clusters of
/// 1, 15, 16, 17 and 40 rows, a rank-0 cluster, a cluster richer than its rows,
/// means, and a lattice with directions no basis touches.
Model randomModel(CoeffPrecision precision, bool mean, unsigned seed, int globalBases = 9) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss;
  Model m;
  auto& g = m.geometry;
  g.camera.size = {10, 10};
  g.cubemapResolution = 2;  // l = 24
  const std::vector<int> sizes{1, 15, 16, 17, 40, 3, 5};
  const std::vector<int> ranks{1, 4, 0, 6, 9, 5, 2};
  long long rows = 0;
  for (int s : sizes) rows += s;
  for (long long r = 0; r < rows; ++r) {
    g.pixels.push_back(static_cast<int>(r));
    g.coverage.push_back(1);
    for (int c = 0; c < 3; ++c) g.albedo.push_back(0.2f + 0.1f * c + 0.001f * r);
  }
  const int n = globalBases;
  m.globalBasis = Eigen::MatrixXf::NullaryExpr(24, n, [&] { return gauss(rng); });
  m.globalBasis.row(5).setZero();  // a direction no pixel sees
  m.hasMean = mean;
  m.precision = precision;
  std::vector<std::int32_t> order(rows);
  for (long long r = 0; r < rows; ++r) order[r] = static_cast<int>((r * 37) % rows);  // shuffled
  m.clusterRows = order;
  m.rowOffsets = {0};
  m.basisOffsets = {0};
  m.coefficientOffsets = {0};
  for (size_t c = 0; c < sizes.size(); ++c) {
    m.rowOffsets.push_back(m.rowOffsets.back() + sizes[c]);
    m.ranks.push_back(ranks[c]);
    for (int i = 0; i < n * ranks[c]; ++i) m.bases.push_back(gauss(rng));
    m.basisOffsets.push_back(m.bases.size());
    for (int i = 0; i < n; ++i) m.means.push_back(mean ? gauss(rng) : 0.0f);
    const long long count = static_cast<long long>(sizes[c]) * ranks[c];
    std::vector<float> u(count);
    for (auto& v : u) v = gauss(rng);
    appendCoefficients(m, u, ranks[c]);
  }
  return m;
}

LatticeLighting randomLighting(int l, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 2);
  LatticeLighting lighting(3 * l);
  for (auto& v : lighting) v = u(rng);
  return lighting;
}

TEST(ModelRelighter, MatchesThePlainReferenceOnEveryShapeAndPrecision) {
  for (CoeffPrecision p : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8})
    for (bool mean : {false, true}) {
      const Model m = randomModel(p, mean, 7);
      const LatticeLighting lighting = randomLighting(24, 3);
      const auto reference = relightModelReference(m, {lighting})[0];
      ModelRelighter relighter(m);
      const auto fast = relighter.relight(lighting);
      // Float sums of a few dozen terms against the double reference.
      EXPECT_LT(maxRelativeDifference(fast, reference), 1e-5)
          << coeffPrecisionName(p) << (mean ? " with mean" : "");
    }
}

TEST(ModelRelighter, LocalLightsMatchThePlainReferenceOnEveryShapeAndPrecision) {
  // Each pixel sees the lights as its own lattice lighting: the reference
  // relights the whole model under each pixel's and keeps that pixel.
  const CubeLattice lattice(2);
  const std::vector<LocalLight> lights{parseLocalLight("point:0.3,2,-0.5,3,2,1"),
                                       parseLocalLight("sphere:-1,0.5,2,0.6,4"),
                                       parseLocalLight("spot:0,-3,0,0.2,1,0,60,5")};
  for (CoeffPrecision p : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8})
    for (bool mean : {false, true}) {
      Model m = randomModel(p, mean, 7);
      for (long long r = 0; r < m.rows(); ++r)
        m.geometry.positions.insert(m.geometry.positions.end(),
                                    {0.1f * (r % 7) - 0.3f, 0.05f * (r % 5), -0.02f * r});
      std::vector<float> reference(3 * m.rows());
      for (long long r = 0; r < m.rows(); ++r) {
        const Vec3 at(m.geometry.positions[3 * r], m.geometry.positions[3 * r + 1],
                      m.geometry.positions[3 * r + 2]);
        const auto image = relightModelReference(m, {localLighting(lights, lattice, at)})[0];
        std::copy(image.begin() + 3 * r, image.begin() + 3 * r + 3, reference.begin() + 3 * r);
      }
      ModelRelighter relighter(m);
      requireLocalLightsApply(relighter.geometry(), "random.h5", true, lights);
      EXPECT_LT(maxRelativeDifference(modelLocalRelight(relighter, lights, 0), reference), 1e-5)
          << coeffPrecisionName(p) << (mean ? " with mean" : "");
    }
}

TEST(ModelRelighter, LocalLightsSharedAtAnchorsStayCloseToEachPixelsOwn) {
  // The small plant (a 6x8x8 lattice: texels of 11 degrees), every light
  // kind from near (0.5 scene radii off the leaves) to far: pixels that share
  // a group's direction taps against every pixel seeing the light exactly.
  const TransportReader t(test::fixture("small-plant"));
  CompressOptions options;
  options.method = Method::AdaptiveQuad;
  const Model model = compressTransport(t, options);
  ModelRelighter relighter(model);
  for (const char* spec : {"point:0.3,2.2,0.8,5", "sphere:-1,1.6,1.4,0.3,40",
                           "spot:0,3,1,0,-1,-0.3,40,9", "point:3,5,6,60"}) {
    const std::vector<LocalLight> light{parseLocalLight(spec)};
    requireLocalLightsApply(relighter.geometry(), "small-plant", true, light);
    const auto exact = modelLocalRelight(relighter, light, 0);
    // Measured here: at most 0.9% at a quarter texel (2.8 degrees on this
    // coarse lattice), at most 2.4% at the default half texel.
    for (const auto& [spread, bound] : {std::pair{0.25, 0.01}, {kAnchorSpreadTexels, 0.03}}) {
      const auto shared = modelLocalRelight(relighter, light, spread);
      double err = 0, norm = 0;
      for (size_t i = 0; i < exact.size(); ++i)
        err += std::pow(shared[i] - exact[i], 2), norm += std::pow(exact[i], 2);
      ASSERT_GT(norm, 0) << spec;
      EXPECT_LT(std::sqrt(err / norm), bound) << spec << " at " << spread << " texels";
      RecordProperty(concat("anchor_error ", spec, " ", spread),
                     std::to_string(std::sqrt(err / norm)));
    }
  }
}

// Columns kept from earlier frames (a light path, the viewer) give the very
// bytes a fresh relight gives: what was relit before does not show. A point
// light touches few texels (their columns kept); a near sphere covers many,
// where projecting a cluster's groups whole can be the cheaper way.
TEST(ModelRelighter, KeptColumnsGiveTheBytesOfAFreshRelight) {
  const TransportReader t(test::fixture("small-plant"));
  CompressOptions options;
  options.method = Method::AdaptiveQuad;
  options.coeffs = CoeffPrecision::F16;
  options.bases = CoeffPrecision::F16;  // the half bases widened as read
  const Model model = compressTransport(t, options);
  ModelRelighter relighter(model);
  LocalLightColumns kept(relighter.packed());
  std::vector<std::vector<LocalLight>> path;
  for (int k = 0; k < 6; ++k)
    path.push_back({parseLocalLight(concat("point:", 0.3 + 0.2 * k, ",2.2,0.8,5")),
                    parseLocalLight(concat("sphere:-1,", 1.6 + 0.05 * k, ",1.4,0.6,40"))});
  for (const auto& lights : path) {
    requireLocalLightsApply(relighter.geometry(), "small-plant", true, lights);
    const auto fresh = modelLocalRelight(relighter, lights);
    const auto reused = modelLocalRelight(relighter, lights, kAnchorSpreadTexels, &kept);
    ASSERT_EQ(fresh.size(), reused.size());
    EXPECT_EQ(0, std::memcmp(fresh.data(), reused.data(), fresh.size() * sizeof(float)))
        << lights[0].spec;
  }
  EXPECT_GT(kept.keptValues(), 0);
  kept.clear();
  EXPECT_EQ(kept.keptValues(), 0);
  const auto again = modelLocalRelight(relighter, path[0], kAnchorSpreadTexels, &kept);
  EXPECT_EQ(again, modelLocalRelight(relighter, path[0]));
}

TEST(ModelRelighter, LocalLightsNeedPositionsAndLightsOffTheSurfaces) {
  Model m = randomModel(CoeffPrecision::F32, false, 3);
  const std::vector<LocalLight> lamp{parseLocalLight("sphere:0,0,0,0.5,1")};
  try {
    requireLocalLightsApply(m.geometry, "old.h5", true, lamp);
    FAIL() << "a model without positions was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("old.h5: has no pixel positions"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("compress (or build) it again"), std::string::npos);
  }
  m.geometry.positions.assign(3 * m.rows(), 2.0f);
  std::fill_n(m.geometry.positions.begin() + 3 * 17, 3, 0.1f);  // row 17, pixel (7, 1): inside
  try {
    requireLocalLightsApply(m.geometry, "m.h5", true, lamp);
    FAIL() << "a sphere around a pixel's position was accepted";
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.parameter(), "light");
    EXPECT_NE(e.problem().find("encloses 1 pixel position(s) of m.h5, the first at pixel (7, 1)"),
              std::string::npos)
        << e.what();
  }
}

TEST(ModelRelighter, EveryKernelLevelGivesTheSameImageWithinRounding) {
  const std::vector<kernels::Level> levels = kernels::supportedLevels();
  ASSERT_FALSE(levels.empty());
  EXPECT_EQ(levels.front(), kernels::Level::Portable);
  std::string names;
  for (kernels::Level level : levels) names += std::string(" ") + kernels::kLevelNames.name(level);
  RecordProperty("kernel_levels", names);
  const kernels::Level before = kernels::activeLevel();
  // 37 global bases: two 16-wide vector steps and a tail in every dot product.
  const LatticeLighting lighting = randomLighting(24, 5);
  for (CoeffPrecision p : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8})
    for (bool mean : {false, true})
      for (bool halfBases : {false, true}) {
        Model m = randomModel(p, mean, 11, 37);
        if (halfBases) {
          m.basisPrecision = CoeffPrecision::F16;
          roundToHalf(m.bases);
        }
        const auto reference = relightModelReference(m, {lighting})[0];
        for (kernels::Level level : levels) {
          kernels::useLevel(level);
          const auto image = ModelRelighter(m).relight(lighting);
          EXPECT_LT(maxRelativeDifference(image, reference), 1e-5)
              << kernels::kLevelNames.name(level) << " " << coeffPrecisionName(p)
              << (mean ? " with mean" : "") << (halfBases ? ", f16 bases" : "");
        }
      }
  kernels::useLevel(before);
  if (levels.back() != kernels::Level::Avx512) {
    EXPECT_THROW(kernels::useLevel(kernels::Level::Avx512), UserError);
  }
}

// One channel of a chunk (local lights' shading) at every level against the
// sum in double: ranks of 0 to 37 (every unrolled step and tail), each
// precision, a base term.
TEST(ModelRelighter, OneChannelChunksAtEveryKernelLevelMatchTheSumInDouble) {
  using kernels::kChunkRows;
  std::mt19937 rng(3);
  std::normal_distribution<float> gauss;
  const kernels::Level before = kernels::activeLevel();
  for (int rank : {0, 1, 3, 4, 5, 8, 17, 37}) {
    std::vector<float> u(static_cast<size_t>(rank) * kChunkRows), t(rank);
    for (auto& v : u) v = gauss(rng);
    for (auto& v : t) v = gauss(rng);
    std::vector<std::uint16_t> half(u.size());
    floatToHalf(u.data(), half.data(), static_cast<long long>(u.size()));
    std::vector<std::int8_t> bytes(u.size());
    for (size_t i = 0; i < u.size(); ++i)
      bytes[i] = static_cast<std::int8_t>(std::clamp(std::lround(40 * u[i]), -127L, 127L));
    std::vector<float> widened(u.size()), stepped(u.size());
    halfToFloat(half.data(), widened.data(), static_cast<long long>(u.size()));
    for (size_t i = 0; i < u.size(); ++i) stepped[i] = bytes[i];
    const float base = 0.25f;
    for (kernels::Level level : kernels::supportedLevels()) {
      kernels::useLevel(level);
      const auto check = [&](const auto* coefficients, const std::vector<float>& asFloat,
                             const char* what) {
        float out[kChunkRows];
        kernels::shadeChunkOne(coefficients, t.data(), rank, base, out);
        for (int lane = 0; lane < kChunkRows; ++lane) {
          double sum = base, scale = std::abs(base);
          for (int k = 0; k < rank; ++k) {
            sum += double(asFloat[k * kChunkRows + lane]) * t[k];
            scale += std::abs(double(asFloat[k * kChunkRows + lane]) * t[k]);
          }
          EXPECT_NEAR(out[lane], sum, 1e-6 * scale)
              << kernels::kLevelNames.name(level) << " " << what << " rank " << rank;
        }
      };
      check(u.data(), u, "f32");
      check(half.data(), widened, "f16");
      check(bytes.data(), stepped, "i8");
    }
  }
  kernels::useLevel(before);
}

/// The model truncated to its clusters' first k bases, as a model of its own.
Model truncated(const Model& m, int k) {
  Model t = m;
  t.bases.clear();
  t.coeffF32.clear();
  t.basisOffsets = {0};
  t.coefficientOffsets = {0};
  const int n = m.globalBases();
  for (int c = 0; c < m.clusters(); ++c) {
    const int r = std::min(k, m.ranks[c]);
    t.ranks[c] = r;
    t.bases.insert(t.bases.end(), m.bases.begin() + m.basisOffsets[c],
                   m.bases.begin() + m.basisOffsets[c] + static_cast<long long>(r) * n);
    t.basisOffsets.push_back(t.bases.size());
    const long long rows = m.rowOffsets[c + 1] - m.rowOffsets[c];
    for (long long row = 0; row < rows; ++row)
      for (int j = 0; j < r; ++j) t.coeffF32.push_back(m.coefficient(c, row, j));
    t.coefficientOffsets.push_back(t.coeffF32.size());
  }
  return t;
}

TEST(ModelRelighter, ShadingInImageBandsGivesEveryRowAndPixelItsValue) {
  const LatticeLighting lighting = randomLighting(24, 8);
  for (CoeffPrecision p : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8}) {
    const Model m = bandedModel(p, 3);
    ASSERT_GT(m.geometry.rows(), 2 * 8192) << "spans three bands";
    const auto reference = relightModelReference(m, {lighting})[0];
    ModelRelighter relighter(m);
    const std::vector<float> rgb = relighter.relight(lighting);
    EXPECT_LT(maxRelativeDifference(rgb, reference), 1e-5) << coeffPrecisionName(p);
    {
      const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      EXPECT_EQ(relighter.relight(lighting), rgb) << "one thread";
    }
    // Into an image of 3 and 4 channels: coverage x value added to what was
    // there, background pixels untouched.
    for (int channels : {3, 4}) {
      const size_t pixels = static_cast<size_t>(m.geometry.camera.size.pixels());
      std::vector<float> image(pixels * channels, 0.25f), expected = image;
      for (long long r = 0; r < m.geometry.rows(); ++r)
        for (int c = 0; c < 3; ++c)
          expected[channels * static_cast<size_t>(m.geometry.pixels[r]) + c] +=
              m.geometry.coverage[r] * rgb[3 * r + c];
      relighter.relightInto(lighting, image.data(), channels);
      EXPECT_LT(maxRelativeDifference(image, expected), 1e-6)
          << coeffPrecisionName(p) << ", " << channels << " channels";
    }
  }
}

/// Frame k of a group against relight() of its lighting alone: equal bit for bit.
void expectGroupEqualsSingleFrames(ModelRelighter& relighter,
                                   const std::vector<LatticeLighting>& lightings,
                                   const std::string& what) {
  std::vector<std::vector<float>> single;
  for (const auto& l : lightings) single.push_back(relighter.relight(l));
  relighter.lightGroup(lightings);
  ASSERT_EQ(relighter.groupFrames(), lightings.size());
  // Frames shaded in any order read only their own projections.
  for (size_t k = lightings.size(); k-- > 0;) {
    std::vector<float> rgb(3 * relighter.rows());
    relighter.shadeFrame(k, rgb.data());
    EXPECT_EQ(rgb, single[k]) << what << ", frame " << k << " of " << lightings.size();
  }
  const size_t pixels = static_cast<size_t>(relighter.geometry().camera.size.pixels());
  std::vector<float> image(pixels * 4, 0.5f), expected = image;
  relighter.relightInto(lightings.back(), expected.data(), 4);
  relighter.lightGroup(lightings);
  relighter.shadeFrameInto(lightings.size() - 1, image.data(), 4);
  EXPECT_EQ(image, expected) << what << ", into an image";
}

TEST(ModelRelighter, AGroupOfFramesEqualsEachFrameAloneBitForBit) {
  std::vector<LatticeLighting> lightings;
  for (unsigned seed = 0; seed < 5; ++seed) lightings.push_back(randomLighting(24, 40 + seed));
  for (CoeffPrecision p : {CoeffPrecision::F32, CoeffPrecision::F16, CoeffPrecision::I8}) {
    ModelRelighter spans(bandedModel(p, 5));
    expectGroupEqualsSingleFrames(spans, lightings, coeffPrecisionName(p));
    spans.setMaxRank(2);
    expectGroupEqualsSingleFrames(spans, lightings,
                                  std::string(coeffPrecisionName(p)) + ", rank <= 2");
    ModelRelighter small(randomModel(p, true, 9));
    // A group larger than any before, then a smaller one in the same scratch.
    expectGroupEqualsSingleFrames(small, lightings, std::string(coeffPrecisionName(p)) + " 5");
    expectGroupEqualsSingleFrames(small, {lightings[1], lightings[3]},
                                  std::string(coeffPrecisionName(p)) + " 2");
  }
}

TEST(ModelRelighter, MaxRankEqualsTheTruncatedModel) {
  const Model m = randomModel(CoeffPrecision::F32, true, 11);
  const LatticeLighting lighting = randomLighting(24, 5);
  ModelRelighter relighter(m);
  for (int k : {0, 1, 3, 100}) {
    relighter.setMaxRank(k);
    const auto reference = relightModelReference(truncated(m, k), {lighting})[0];
    EXPECT_LT(maxRelativeDifference(relighter.relight(lighting), reference), 1e-5) << k;
  }
  // A fraction: ceil(0.5 n_i) of ranks {1, 4, 0, 6, 9, 5, 2} is {1, 2, 0, 3, 5, 3, 1}.
  relighter.setRankFraction(0.5);
  const long long full = ModelRelighter(m).bytesPerFrame();
  EXPECT_LT(relighter.bytesPerFrame(), full);
  relighter.setMaxRank(-1);
  EXPECT_EQ(relighter.bytesPerFrame(), full);
  EXPECT_THROW(relighter.setRankFraction(1.5), UserError);
}

/// Every global basis and every cluster basis kept: a model equal to T.
CompressOptions keepingEverything(Method method) {
  CompressOptions o;
  o.method = method;
  o.globalEnergy = 1;
  o.tolerance = 1;
  o.clusters = 4;
  return o;
}

class RelightPlant : public test::SmallPlantSuite {
 protected:
  static std::vector<LatticeLighting> lightings() { return test::plantLightings(); }
};

TEST_F(RelightPlant, KeepingEverythingMatchesTheDenseRelight) {
  const TransportReader t(path());
  const CubeLattice lattice(8);
  std::vector<LatticeLighting> lightings;
  for (const char* env : {"sky", "sun:50,30,4,1000"})
    lightings.push_back(computeLighting(*loadEnvironment(env), lattice, {}));
  const auto dense = denseRelight(t, lightings);
  for (Method method : {Method::Global, Method::Block, Method::Cpca, Method::AdaptiveQuad,
                        Method::AdaptiveBinary}) {
    const Model m = compressTransport(t, keepingEverything(method));
    EXPECT_LT(m.transportError, 1e-4) << methodName(method);
    const auto relit = relightModelReference(m, lightings);
    for (size_t k = 0; k < lightings.size(); ++k)
      EXPECT_LT(relativeL2(relit[k], dense[k]), 1e-4) << methodName(method);
  }
}

TEST_F(RelightPlant, KeepingEverythingEqualsTheDenseRelight) {
  const TransportReader t(path());
  const auto all = lightings();
  const auto dense = denseRelight(t, all);
  for (Method method : {Method::Global, Method::Cpca, Method::AdaptiveQuad}) {
    ModelRelighter relighter(compressTransport(t, keepingEverything(method)));
    for (size_t k = 0; k < all.size(); ++k)
      EXPECT_LT(relativeL2(relighter.relight(all[k]), dense[k]), 1e-4) << methodName(method);
  }
}

TEST(RelightBouncedPlant, RgbRowsKeptWholeRelightAsTheDenseTransport) {
  const TransportReader t(test::fixture("bounced-plant"));
  ASSERT_EQ(t.header().channels, 3);
  const auto all = test::plantLightings();
  const auto dense = denseRelight(t, all);
  for (Method method :
       {Method::Global, Method::Cpca, Method::AdaptiveQuad, Method::AdaptiveBinary}) {
    const Model m = compressTransport(t, keepingEverything(method));
    EXPECT_EQ(m.geometry.channels, 3);
    EXPECT_EQ(m.globalBasis.rows(), 3 * t.latticeSize());
    EXPECT_LT(m.transportError, 1e-4) << methodName(method);
    const auto reference = relightModelReference(m, all);
    ModelRelighter relighter(m);
    for (size_t k = 0; k < all.size(); ++k) {
      EXPECT_LT(relativeL2(reference[k], dense[k]), 1e-4) << methodName(method);
      EXPECT_LT(relativeL2(relighter.relight(all[k]), dense[k]), 1e-4) << methodName(method);
    }
    // R, G and B rows: each channel's third of V_g meets the group's lightings too.
    expectGroupEqualsSingleFrames(relighter, all, methodName(method));
  }
}

TEST(RelightBouncedPlant, ChannelsMeetOnlyTheirOwnLight) {
  // Red light alone lights only the red channel, through the red third of the rows.
  const TransportReader t(test::fixture("bounced-plant"));
  const int l = t.latticeSize();
  LatticeLighting red = test::plantLightings()[0];
  for (int j = 0; j < l; ++j) red[3 * j + 1] = red[3 * j + 2] = 0;
  const auto dense = denseRelight(t, {red})[0];
  std::vector<float> rows(static_cast<size_t>(t.rows()) * t.rowLength());
  t.readRows(0, t.rows(), rows.data());
  double lit = 0;
  for (long long r = 0; r < t.rows(); ++r) {
    double expected = 0;
    for (int j = 0; j < l; ++j) expected += double(rows[r * 3 * l + j]) * red[3 * j];
    expected *= t.header().albedo[3 * r];
    EXPECT_NEAR(dense[3 * r], expected, 1e-5 * std::max(1.0, expected));
    EXPECT_EQ(dense[3 * r + 1], 0.0f);
    EXPECT_EQ(dense[3 * r + 2], 0.0f);
    lit += expected;
  }
  EXPECT_GT(lit, 0);
  ModelRelighter relighter(compressTransport(t, keepingEverything(Method::Global)));
  const auto fast = relighter.relight(red);
  for (long long r = 0; r < t.rows(); ++r) {
    EXPECT_EQ(fast[3 * r + 1], 0.0f);
    EXPECT_EQ(fast[3 * r + 2], 0.0f);
  }
}

TEST_F(RelightPlant, CompressedModelsMatchTheReferenceWithOneOrTwoThreads) {
  const TransportReader t(path());
  const auto all = lightings();
  for (Method method : {Method::Block, Method::AdaptiveBinary}) {
    CompressOptions o;
    o.method = method;
    o.clusters = 3;
    o.coeffs = CoeffPrecision::F16;
    const Model m = compressTransport(t, o);
    ModelRelighter relighter(m);
    const auto reference = relightModelReference(m, all);
    for (size_t k = 0; k < all.size(); ++k) {
      const auto two = relighter.relight(all[k]);
      std::vector<float> one;
      {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = relighter.relight(all[k]);
      }
      EXPECT_EQ(one, two) << methodName(method);
      EXPECT_LT(maxRelativeDifference(two, reference[k]), 1e-5) << methodName(method);
    }
  }
}

TEST_F(RelightPlant, QuantizedCoefficientsStayWithinTheirStepBound) {
  // b_p = albedo_p sum_k u_pk L_ik, so a coefficient error |du_pk| moves the
  // pixel by at most albedo_p sum_k |du_pk| |L_ik|. Per coefficient, half keeps
  // 11 significant bits: |du| <= 2^-11 |u| (+ 2^-25 for subnormals); i8 rounds
  // to the nearest step s_ik = max over the cluster's rows of |u_k| / 127: |du| <= s_ik / 2.
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveQuad;
  o.block = 16;
  const Model f32 = compressTransport(t, o);
  o.coeffs = CoeffPrecision::F16;
  const Model f16 = compressTransport(t, o);
  o.coeffs = CoeffPrecision::I8;
  const Model i8 = compressTransport(t, o);
  ASSERT_EQ(f16.bases, f32.bases);
  ASSERT_EQ(i8.bases, f32.bases);
  const int n = f32.globalBases();
  ModelRelighter exact(f32), half(f16), byte(i8);
  for (const auto& lighting : lightings()) {
    const auto b32 = exact.relight(lighting), b16 = half.relight(lighting),
               b8 = byte.relight(lighting);
    // L_i in double, from the model's own arrays.
    Eigen::MatrixXd lg = Eigen::MatrixXd::Zero(n, 3);
    for (long long j = 0; j < f32.globalBasis.rows(); ++j)
      for (int c = 0; c < 3; ++c)
        lg.col(c) += f32.globalBasis.row(j).transpose().cast<double>() * lighting[3 * j + c];
    double scale = 0;
    for (float v : b32) scale = std::max(scale, double(std::abs(v)));
    const double rounding = 1e-5 * scale;  // float evaluation of both images
    int checked = 0;
    for (int c = 0; c < f32.clusters(); ++c) {
      const Eigen::Map<const Eigen::MatrixXf> w(f32.bases.data() + f32.basisOffsets[c], n,
                                                f32.ranks[c]);
      const Eigen::MatrixXd li = w.cast<double>().transpose() * lg;
      for (long long r = 0; r < f32.rowOffsets[c + 1] - f32.rowOffsets[c]; ++r) {
        const int row = f32.clusterRows[f32.rowOffsets[c] + r];
        for (int ch = 0; ch < 3; ++ch) {
          double halfBound = 0, byteBound = 0;
          for (int k = 0; k < f32.ranks[c]; ++k) {
            const double u = std::abs(f32.coefficient(c, r, k)), l = std::abs(li(k, ch));
            halfBound += (u * std::ldexp(1.0, -11) + std::ldexp(1.0, -25)) * l;
            byteBound += 0.5 * i8.coeffScale[i8.firstBasisIndex(c) + k] * l;
          }
          const double a = f32.geometry.albedo[3 * row + ch];
          EXPECT_LE(std::abs(b16[3 * row + ch] - b32[3 * row + ch]), a * halfBound + rounding);
          EXPECT_LE(std::abs(b8[3 * row + ch] - b32[3 * row + ch]), a * byteBound + rounding);
          ++checked;
        }
      }
    }
    EXPECT_EQ(checked, 3 * f32.rows());
  }
}

TEST_F(RelightPlant, HalfBasesRelightExactlyAndCostLittleError) {
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveQuad;
  o.block = 16;
  const Model full = compressTransport(t, o);
  o.bases = CoeffPrecision::F16;
  o.coeffs = CoeffPrecision::F16;
  const Model half = compressTransport(t, o);
  ASSERT_EQ(half.ranks, full.ranks);
  // The error is recomputed from the stored values: never below the exact
  // fit's, and half rounding (2^-11 relative) adds well under 1% to it.
  EXPECT_GE(half.transportError, full.transportError * (1 - 1e-6));
  EXPECT_LT(half.transportError, full.transportError * 1.01);
  test::TempDir dir;
  writeModel(half, dir.file("m.h5"));
  const Model back = readModel(dir.file("m.h5"));
  EXPECT_EQ(back.basisPrecision, CoeffPrecision::F16);
  EXPECT_EQ(back.bases, half.bases);
  EXPECT_EQ(back.means, half.means);
  ModelRelighter relighter(back);
  EXPECT_LT(relighter.bytesPerFrame(), ModelRelighter(full).bytesPerFrame());
  for (const auto& lighting : lightings())
    EXPECT_LT(maxRelativeDifference(relighter.relight(lighting),
                                    relightModelReference(half, {lighting})[0]),
              1e-5);
}

TEST_F(RelightPlant, RelightingStraightIntoTheImageEqualsComposingTheRows) {
  const TransportReader t(path());
  CompressOptions o;
  o.method = Method::AdaptiveBinary;
  o.clusters = 3;
  const Model m = compressTransport(t, o);
  ModelRelighter relighter(m);
  const auto sky = loadEnvironment("sky");
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()).matrix();
  const ImageComposer composer(m.geometry);
  const LatticeLighting lighting = lightings()[0];
  for (Background bg : {Background::Env, Background::Black, Background::Alpha}) {
    const Image composed =
        composeImage(m.geometry, relighter.relight(lighting), bg, *sky, rotation);
    std::vector<float> direct(composed.pixels.size(), -1.0f);
    composer.background(bg, *sky, rotation, direct.data());
    relighter.relightInto(lighting, direct.data(), ImageComposer::channels(bg));
    EXPECT_EQ(direct, composed.pixels) << kBackgroundNames.name(bg);
  }
}

TEST_F(RelightPlant, LargeClustersFittedBlockwiseGiveTheSameModel) {
  // The blocked Gram path (for clusters too big to copy in double) against the
  // direct one, on the same global projection.
  const TransportReader t(path());
  const GlobalBasis basis = computeGlobalBasis(t, {0.999, 16384, 1});
  const GlobalProjection projection = projectOntoBasis(t, basis);
  ClusterInput in{&projection.coefficients, &t.header().pixels, t.header().camera.size, 0.99, true};
  for (const Partition& partition : {singleCluster(in), fixedBlocks(in, 8)}) {
    ModelOptions o;
    o.tolerance = 0.99;
    o.mean = true;
    o.floatFits = false;
    const Model direct = buildModel(t.header(), basis, projection, partition, o);
    o.floatFits = true;
    const Model inFloat = buildModel(t.header(), basis, projection, partition, o);
    o.largeClusterValues = 0;
    const Model blocked = buildModel(t.header(), basis, projection, partition, o);
    EXPECT_EQ(direct.ranks, blocked.ranks);
    EXPECT_NEAR(direct.transportError, blocked.transportError, 1e-6);
    for (const auto& lighting : lightings())
      EXPECT_LT(maxRelativeDifference(ModelRelighter(blocked).relight(lighting),
                                      ModelRelighter(direct).relight(lighting)),
                1e-4);
    // Fitted in float: the same ranks and error; the bases near each cut may
    // turn a little within nearly equal eigenvalues (float rounding over the
    // eigengap), which moves pixels by far less than the error itself. How
    // far the error moves depends on the BLAS kernels the CPU gets (1.4e-5
    // relative on an AMD EPYC, under 1e-5 on the Intel machines before).
    EXPECT_EQ(inFloat.ranks, direct.ranks);
    EXPECT_NEAR(inFloat.transportError, direct.transportError, 1e-4 * direct.transportError);
    for (const auto& lighting : lightings())
      EXPECT_LT(maxRelativeDifference(ModelRelighter(inFloat).relight(lighting),
                                      ModelRelighter(direct).relight(lighting)),
                1e-3);
  }
}

}  // namespace
}  // namespace acpca
