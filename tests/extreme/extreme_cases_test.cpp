// The extreme-case suite (docs/design.md section 8): lighting, data and geometry at
// their limits. Every method must give finite output, and its error against
// the dense relight must stay within the bound stated for the case:
//  - compressed models: |B - B*| <= eps_T |T|_F |L_c| max albedo_c per channel
//    (Cauchy-Schwarz on every row; eps_T the model's relative transport error),
//    for any lighting however wild;
//  - the Haar baseline keeping every term: the same with eps_T = 2e-3 (half values);
//  - the SH baseline: finite, zero under zero light (a low-frequency fit, no bound).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cluster/compress.h"
#include "eval/error_measures.h"
#include "eval/haar_transport.h"
#include "eval/sh_transport.h"
#include "lighting/lighting.h"
#include "precompute/sampling_advice.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "relight/dense_relight.h"
#include "relight/model_relighter.h"
#include "tests/render_support.h"

namespace acpca {
namespace {

using test::TempDir;

bool allFinite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

double norm(const std::vector<float>& v) {
  double s = 0;
  for (float x : v) s += double(x) * x;
  return std::sqrt(s);
}

/// The bound above for relative transport error eps over T of Frobenius norm tNorm.
double imageErrorBound(double eps, double tNorm, const LatticeLighting& l,
                       const std::vector<float>& albedo) {
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    double light = 0, a = 0;
    for (size_t j = 0; j < l.size() / 3; ++j) light += l[3 * j + c] * l[3 * j + c];
    for (size_t p = 0; p < albedo.size() / 3; ++p) a = std::max(a, double(albedo[3 * p + c]));
    sum += std::pow(a * eps * tNorm * std::sqrt(light), 2);
  }
  return std::sqrt(sum);
}

std::vector<float> difference(const std::vector<float>& a, const std::vector<float>& b) {
  std::vector<float> d(a.size());
  for (size_t i = 0; i < a.size(); ++i) d[i] = a[i] - b[i];
  return d;
}

/// The extreme lightings on a lattice, by name.
std::vector<std::pair<std::string, LatticeLighting>> extremeLightings(const CubeLattice& lattice) {
  std::vector<std::pair<std::string, LatticeLighting>> out;
  out.emplace_back("all black", LatticeLighting(3 * lattice.size(), 0.0));
  out.emplace_back("constant:1", computeLighting(*loadEnvironment("constant:1"), lattice, {}));
  LatticeLighting texel(3 * lattice.size());
  for (int j = 0; j < lattice.size(); ++j)
    for (int c = 0; c < 3; ++c)
      texel[3 * j + c] = (j == lattice.size() / 3 + 5 ? 1e6 : 1e-3) * lattice.solidAngle(j);
  out.emplace_back("one texel at 1e6, the rest 1e-3", texel);
  // A lat-long map whose pixels span 1e-6..1e6, log-uniform.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> exponent(-6, 6);
  std::vector<float> pixels(64 * 32 * 3);
  for (auto& v : pixels) v = static_cast<float>(std::pow(10.0, exponent(rng)));
  out.emplace_back("dynamic range 1e-6..1e6",
                   computeLighting(*makeLatLongEnvironment("range", 64, 32, pixels), lattice, {}));
  out.emplace_back("sun of 0.5 degrees",
                   computeLighting(*loadEnvironment("sun:40,60,0.5,100000"), lattice, {}));
  return out;
}

class ExtremeLighting : public test::SmallPlantSuite {};

TEST_F(ExtremeLighting, EveryMethodStaysFiniteAndWithinItsBound) {
  const TransportReader transport(path());
  const TransportHeader& h = transport.header();
  const CubeLattice lattice(h.cubemapResolution);
  std::vector<float> rows(transport.rows() * transport.latticeSize());
  transport.readRows(0, transport.rows(), rows.data());
  const double tNorm = norm(rows);

  std::vector<std::pair<std::string, Model>> models;
  for (Method m : {Method::Global, Method::Block, Method::Cpca, Method::AdaptiveQuad,
                   Method::AdaptiveBinary}) {
    CompressOptions o;
    o.method = m;
    o.tolerance = 0.99;
    o.globalEnergy = 0.999;
    o.clusters = 6;
    Model model = compressTransport(transport, o);
    // Each cluster keeps 99% of its energy inside a basis that keeps 99.9%.
    EXPECT_LE(model.transportError, std::sqrt(0.001 + 0.01) * 1.001) << methodName(m);
    models.emplace_back(methodName(m), std::move(model));
  }
  {
    CompressOptions o;
    o.method = Method::AdaptiveBinary;
    o.coeffs = CoeffPrecision::I8;
    o.bases = CoeffPrecision::F16;
    models.emplace_back("adaptive-binary i8 coefficients, f16 bases",
                        compressTransport(transport, o));
  }
  HaarTransport haar(transport, 0);
  ShTransport sh(transport, 16, 4);
  const ShCoefficients shFit = sh.fit(16, ShFit::Cls);

  for (const auto& [name, light] : extremeLightings(lattice)) {
    SCOPED_TRACE(name);
    for (double v : light) ASSERT_TRUE(std::isfinite(v) && v >= 0);
    const std::vector<float> truth = denseRelight(transport, {light})[0];
    ASSERT_TRUE(allFinite(truth));
    const bool black = norm(truth) == 0;
    EXPECT_EQ(black, name == "all black");
    for (auto& [method, model] : models) {
      ModelRelighter relighter(model);
      const std::vector<float> image = relighter.relight(light);
      ASSERT_TRUE(allFinite(image)) << method;
      const double bound = imageErrorBound(model.transportError, tNorm, light, h.albedo);
      EXPECT_LE(norm(difference(image, truth)), bound * 1.001 + 1e-5 * norm(truth)) << method;
      if (black) {
        EXPECT_EQ(norm(image), 0.0) << method;
      }
    }
    const std::vector<float> wavelet = haar.relight(light, transport.latticeSize());
    ASSERT_TRUE(allFinite(wavelet));
    EXPECT_LE(norm(difference(wavelet, truth)),
              imageErrorBound(2e-3, tNorm, light, h.albedo) + 1e-5 * norm(truth));
    std::vector<float> harmonic(3 * transport.rows());
    sh.relight(shFit, light, harmonic.data());
    ASSERT_TRUE(allFinite(harmonic));
    if (black) {
      EXPECT_EQ(norm(harmonic), 0.0);
    }
  }
}

TEST(ExtremeLightingEnergy, WideRangeMapsAndTinySunsKeepTheirEnergy) {
  const CubeLattice lattice(16);
  // The 0.5 degree sun: radiance times its disc's solid angle, at any rotation.
  const double disc = 2 * M_PI * (1 - std::cos(0.25 * M_PI / 180));
  for (const EnvRotation& r : {EnvRotation{}, EnvRotation{37, 11, -23}}) {
    const LatticeLighting l = computeLighting(*loadEnvironment("sun:40,60,0.5,100000"), lattice, r);
    double sum = 0;
    for (size_t j = 0; j < l.size(); j += 3) sum += l[j];
    EXPECT_NEAR(sum, 1e5 * disc, 1e-6 * 1e5 * disc);
  }
  // 1e-6..1e6 in one map: every pixel's radiance times its exact solid angle.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> exponent(-6, 6);
  const int w = 64, h = 32;
  std::vector<float> pixels(w * h * 3);
  double expected = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float v = static_cast<float>(std::pow(10.0, exponent(rng)));
      for (int c = 0; c < 3; ++c) pixels[3 * (y * w + x) + c] = v;
      expected +=
          double(v) * (2 * M_PI / w) * (std::cos(M_PI * y / h) - std::cos(M_PI * (y + 1) / h));
    }
  const LatticeLighting l =
      computeLighting(*makeLatLongEnvironment("range", w, h, pixels), lattice, {});
  double sum = 0, smallest = INFINITY;
  for (size_t j = 0; j < l.size(); j += 3) sum += l[j], smallest = std::min(smallest, l[j]);
  EXPECT_NEAR(sum, expected, 1e-9 * expected);
  EXPECT_GT(smallest, 0.0);
}

/// A transport file of 16x16 pixels on a 6x4x4 lattice: the left half fully
/// shadowed (zero rows), the right half drawn from a rank-5 subspace.
std::string writeShadowedTransport(const TempDir& dir) {
  TransportHeader h;
  h.camera.size = {16, 16};
  h.cubemapResolution = 4;
  h.precision = Precision::F32;
  h.scene = "synthetic";
  for (int p = 0; p < 256; ++p) {
    h.pixels.push_back(p);
    h.albedo.insert(h.albedo.end(), {0.5f, 0.6f, 0.7f});
    h.coverage.push_back(1.0f);
    h.normals.insert(h.normals.end(), {0.0f, 1.0f, 0.0f});
  }
  const int l = h.latticeSize();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0, 1);
  std::vector<std::vector<float>> basis(5, std::vector<float>(l));
  for (auto& b : basis)
    for (auto& v : b) v = uniform(rng);
  std::vector<float> rows(256 * l, 0.0f);
  for (int p = 0; p < 256; ++p) {
    if (p % 16 < 8) continue;  // shadowed
    for (const auto& b : basis) {
      const float weight = uniform(rng);
      for (int j = 0; j < l; ++j) rows[p * l + j] += weight * b[j];
    }
  }
  const std::string path = dir.file("shadowed.h5");
  TransportWriter writer(path, h);
  writer.writeRows(0, 256, rows.data());
  writer.finish();
  return path;
}

TEST(ExtremeData, ShadowedClustersGetRankZeroAndNoClusterOutranksItsRows) {
  TempDir dir;
  const TransportReader transport(writeShadowedTransport(dir));
  const CubeLattice lattice(4);
  const LatticeLighting sky = computeLighting(*loadEnvironment("sky"), lattice, {});
  const std::vector<float> truth = denseRelight(transport, {sky})[0];
  std::vector<float> rows(256 * transport.latticeSize());
  transport.readRows(0, 256, rows.data());
  for (Method m : {Method::Global, Method::Block, Method::Cpca, Method::AdaptiveQuad,
                   Method::AdaptiveBinary}) {
    for (int clusters : {4, 200}) {  // 200: clusters of one or two rows, smaller than the rank
      SCOPED_TRACE(concat(methodName(m), ", ", clusters, " clusters"));
      CompressOptions o;
      o.method = m;
      o.clusters = clusters;
      o.block = 2;
      o.tolerance = 0.9999;
      o.globalEnergy = 1.0;
      const Model model = compressTransport(transport, o);
      for (int c = 0; c < model.clusters(); ++c) {
        const long long size = model.rowOffsets[c + 1] - model.rowOffsets[c];
        EXPECT_LE(model.ranks[c], size) << "cluster " << c;
        EXPECT_LE(model.ranks[c], 5) << "cluster " << c;
        bool shadowed = true;
        for (auto i = model.rowOffsets[c]; i < model.rowOffsets[c + 1]; ++i)
          shadowed = shadowed && model.clusterRows[i] % 16 < 8;
        if (shadowed) {
          EXPECT_EQ(model.ranks[c], 0) << "cluster " << c << " of zero rows";
        }
      }
      EXPECT_LE(model.transportError, 0.011);
      ModelRelighter relighter(model);
      const std::vector<float> image = relighter.relight(sky);
      ASSERT_TRUE(allFinite(image));
      for (int p = 0; p < 256; ++p) {
        if (p % 16 >= 8) continue;
        for (int c = 0; c < 3; ++c)
          ASSERT_LE(std::abs(image[3 * p + c]), 1e-6f * (1 + truth[3 * p + c])) << "pixel " << p;
      }
      // A shadowed row in a cluster with lit ones is the mean plus its bases: zero to rounding.
      EXPECT_LT(relativeL2(image, truth), 0.011);
    }
  }
}

/// A diffuse floor alone: every row is cos+ / pi of its texel, the same for
/// every pixel: rank one.
Scene floorScene(double viewFromNormalDegrees) {
  Scene s{"floor", {}, {}, {}, {}, {}};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 40, {}, "floor"));
  const double a = viewFromNormalDegrees * M_PI / 180;
  s.camera.eye = {0, 6 * std::cos(a), 6 * std::sin(a)};
  s.camera.target = {0, 0, 0};
  s.camera.fovDegrees = 20;
  s.camera.size = {24, 24};
  return s;
}

TEST(ExtremeGeometry, AFloorIsRankOneSeenFromAboveOrGrazingAt89Degrees) {
  for (double view : {30.0, 89.0}) {
    SCOPED_TRACE(concat("camera ", view, " degrees from the normal"));
    TempDir dir;
    PrecomputeOptions po;
    po.cubemapResolution = 8;
    po.precision = Precision::F32;
    precomputeTransport(floorScene(view), dir.file("t.h5"), po);
    const TransportReader transport(dir.file("t.h5"));
    ASSERT_GT(transport.rows(), 20);
    const CubeLattice lattice(8);
    std::vector<float> rows(transport.rows() * lattice.size());
    transport.readRows(0, transport.rows(), rows.data());
    // No self-shadowing even at grazing view: the analytic row everywhere.
    for (long long p = 0; p < transport.rows(); ++p)
      for (int j = 0; j < lattice.size(); ++j)
        ASSERT_NEAR(rows[p * lattice.size() + j], std::max(0.0, lattice.direction(j).y()) / M_PI,
                    1e-6)
            << "row " << p << " texel " << j;
    const LatticeLighting sky = computeLighting(*loadEnvironment("sky"), lattice, {});
    const std::vector<float> truth = denseRelight(transport, {sky})[0];
    for (Method m : {Method::Global, Method::Cpca, Method::AdaptiveQuad, Method::AdaptiveBinary}) {
      CompressOptions o;
      o.method = m;
      const Model model = compressTransport(transport, o);
      EXPECT_EQ(model.globalBases(), 1) << methodName(m);
      for (int r : model.ranks) EXPECT_LE(r, 1) << methodName(m);
      ModelRelighter relighter(model);
      EXPECT_LT(relativeL2(relighter.relight(sky), truth), 1e-5) << methodName(m);
    }
  }
}

/// Integral over the upper hemisphere of n of the normalized Phong lobe around
/// the mirror direction r times the cosine: the reflectance under constant light
/// (ks = 1), by a fine midpoint rule in polar angles around r.
double phongReflectance(const Vec3& n, const Vec3& r, double s) {
  const Vec3 u = r.unitOrthogonal(), w = r.cross(u);
  // The lobe is below 1e-12 of its peak past this angle from r.
  const double reach = s > 1 ? std::min(M_PI, std::acos(std::exp(std::log(1e-12) / s))) : M_PI;
  const int steps = 600;
  double sum = 0;
  for (int i = 0; i < steps; ++i) {
    const double a = (i + 0.5) * reach / steps;
    for (int k = 0; k < 2 * steps; ++k) {
      const double phi = (k + 0.5) * M_PI / steps;
      const Vec3 d = std::cos(a) * r + std::sin(a) * (std::cos(phi) * u + std::sin(phi) * w);
      const double c = n.dot(d), lobe = std::cos(a);
      if (c > 0 && lobe > 0) sum += std::pow(lobe, s) * c * std::sin(a);
    }
  }
  return sum * (reach / steps) * (M_PI / steps) * (s + 2) / (2 * M_PI);
}

TEST(ExtremeGeometry, PhongLobesFromBroadToNearMirrorIntegrateToTheirReflectance) {
  for (double s : {1.0, 100.0, 1000.0, 5000.0}) {
    SCOPED_TRACE(concat("Phong exponent ", s));
    Scene scene = makeBuiltinScene("sphere");
    scene.camera.eye = {0, 0, 4.5};
    scene.camera.size = {33, 33};
    scene.spheres[0].material = {Material::Type::Phong, {0.5f, 0.5f, 0.5f}, 1.0, s};
    PrecomputeOptions po;
    po.cubemapResolution = 16;
    po.precision = Precision::F32;
    // At one ray per texel of a 6x16x16 lattice, lobes from s = 100 on are
    // under-sampled (a warning says so); texelRaysForLobe resolves them.
    const bool sharp = s >= 100;
    EXPECT_EQ(!samplingWarnings(scene, po).empty(), sharp);
    po.texelRays = texelRaysForLobe(s, po.cubemapResolution);
    EXPECT_EQ(po.texelRays > 1, sharp);
    EXPECT_TRUE(samplingWarnings(scene, po).empty());
    TempDir dir;
    precomputeTransport(scene, dir.file("t.h5"), po);
    const TransportReader transport(dir.file("t.h5"));
    const CubeLattice lattice(16);
    std::vector<float> row(lattice.size());
    double sumError = 0, worst = 0;
    int count = 0;
    for (int y = 12; y <= 20; y += 2)
      for (int x = 12; x <= 20; x += 2) {
        const long long r = test::rowOfPixel(transport.header(), x, y);
        ASSERT_GE(r, 0);
        transport.readRows(r, 1, row.data());
        double furnace = 0;
        for (int j = 0; j < lattice.size(); ++j) {
          ASSERT_TRUE(std::isfinite(row[j]));
          furnace += row[j] * lattice.solidAngle(j);
        }
        const float* n = &transport.header().normals[3 * r];
        const Vec3 normal(n[0], n[1], n[2]);  // the unit sphere: the hit point too
        const Vec3 toViewer = (scene.camera.eye - normal).normalized();
        const Vec3 mirrored = 2 * normal.dot(toViewer) * normal - toViewer;
        const double error = std::abs(furnace / phongReflectance(normal, mirrored, s) - 1);
        sumError += error, worst = std::max(worst, error), ++count;
      }
    EXPECT_LT(sumError / count, sharp ? 0.06 : 0.01);
    EXPECT_LT(worst, sharp ? 0.25 : 0.02);
  }
}

TEST(ExtremeGeometry, ZeroAreaTrianglesAreLeftOutAndChangeNothing) {
  Scene clean = floorScene(40);
  clean.meshes.push_back(makeBox({-1, 0, -1}, {1, 1, 1}, {}, "box"));
  Scene dirty = clean;
  TriangleMesh& box = dirty.meshes.back();
  const int v = static_cast<int>(box.vertices.size());
  box.vertices.push_back({0, 1, 0});
  box.vertices.push_back({0.5f, 1, 0});
  box.vertices.push_back({1, 1, 0});  // collinear with the two before
  box.triangles.push_back({v, v + 1, v + 2});
  box.triangles.push_back({0, 0, 1});  // a repeated corner
  box.triangles.push_back({v, v, v});  // a point
  TempDir dir;
  PrecomputeOptions po;
  po.cubemapResolution = 8;
  po.precision = Precision::F32;
  const PrecomputeStats cleanStats = precomputeTransport(clean, dir.file("clean.h5"), po);
  const PrecomputeStats dirtyStats = precomputeTransport(dirty, dir.file("dirty.h5"), po);
  EXPECT_EQ(cleanStats.degenerateTriangles, 0);
  EXPECT_EQ(dirtyStats.degenerateTriangles, 3);
  const TransportReader a(dir.file("clean.h5")), b(dir.file("dirty.h5"));
  ASSERT_EQ(a.rows(), b.rows());
  std::vector<float> ra(a.rows() * a.latticeSize()), rb(ra.size());
  a.readRows(0, a.rows(), ra.data());
  b.readRows(0, b.rows(), rb.data());
  EXPECT_EQ(ra, rb);
  EXPECT_TRUE(allFinite(rb));
}

TEST(ExtremeGeometry, NonFiniteVerticesAreRefusedByName) {
  Scene scene = floorScene(40);
  scene.meshes[0].vertices[1].y() = std::numeric_limits<float>::quiet_NaN();
  try {
    scene.validate();
    FAIL() << "a NaN vertex was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("floor"), std::string::npos) << e.what();
  }
  TempDir dir;
  EXPECT_THROW(precomputeTransport(scene, dir.file("t.h5"), {}), UserError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("t.h5")));
}

}  // namespace
}  // namespace acpca
