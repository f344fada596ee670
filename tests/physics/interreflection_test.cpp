// Interreflections against closed forms (docs/scenes.md, "Interreflections"):
// the inside of a hemispherical shell, where each bounce multiplies by a f with
// f = 1/2; a white furnace corner; light from below a shell's rim; no other
// surface, no indirect light; monotone in the bounce count; colour that bleeds;
// the same rows for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "lighting/lighting.h"
#include "precompute/scene.h"
#include "tests/physics/grey_rows.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

using test::LoadedTransport;
using test::precomputeInMemory;

Material grey(float a) {
  return {Material::Type::Diffuse, {a, a, a}};
}

PrecomputeOptions bounceOptions(int bounces, double cacheCell, int cubemap = 16) {
  PrecomputeOptions o;
  o.cubemapResolution = cubemap;
  o.precision = Precision::F32;
  o.samplesPerPixel = 1;
  o.bounces = bounces;
  o.indirectSamples = 64;
  o.indirectCacheCell = cacheCell;
  return o;
}

/// The inside of a thin hemispherical shell of radius 1 opening upwards (rim
/// at y = 1, bottom at y = 0), with its exact normals, seen from its axis.
Scene shellScene(float albedo, int size) {
  Scene s{"shell", {}, {}, {}, {}, {}};
  s.camera.eye = {0, 4.5, 0};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 0, -1};
  s.camera.fovDegrees = 30;
  s.camera.size = {size, size};
  TriangleMesh shell = emptyMesh("shell", grey(albedo));
  const int rings = 64, segments = 128;
  const Vec3 centre(0, 1, 0);
  for (int i = 0; i <= rings; ++i) {
    const double theta = 0.5 * std::numbers::pi * i / rings;  // 0 = bottom, pi/2 = rim
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * std::numbers::pi * k / segments;
      shell.vertices.emplace_back(float(std::sin(theta) * std::cos(phi)),
                                  float(1 - std::cos(theta)),
                                  float(std::sin(theta) * std::sin(phi)));
    }
  }
  const auto normalAt = [&](int v) {
    return Eigen::Vector3f((shell.vertices[v].cast<double>() - centre).normalized().cast<float>());
  };
  const auto add = [&](int a, int b, int c) {
    shell.triangles.emplace_back(a, b, c);
    for (int v : {a, b, c}) shell.normals.push_back(normalAt(v));
  };
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < segments; ++k) {
      const int a = i * segments + k, b = i * segments + (k + 1) % segments;
      if (i > 0) add(a, a + segments, b);  // ring 0 is the bottom point, repeated
      add(b, a + segments, b + segments);
    }
  s.meshes.push_back(std::move(shell));
  return s;
}

/// Rows of the shell's inside away from its rim: the shading normal (towards
/// the centre) points at least 20 degrees up.
std::vector<long long> innerRows(const LoadedTransport& t) {
  std::vector<long long> rows;
  for (long long r = 0; r < t.header.rows(); ++r)
    if (t.header.normals[3 * r + 1] > std::sin(20 * std::numbers::pi / 180)) rows.push_back(r);
  return rows;
}

double meanOver(const std::vector<double>& values, const std::vector<long long>& rows) {
  double sum = 0;
  for (long long r : rows) sum += values[r];
  return sum / double(rows.size());
}

/// a (1 - f)(1 + af + ... + (af)^K) with f = 1/2: any point of a sphere sees
/// a spherical cap over the cosine-weighted share of its view that the cap
/// takes of the sphere's area.
double shellRadiance(double a, int bounces) {
  double sum = 0, term = 1;
  for (int k = 0; k <= bounces; ++k, term *= a / 2) sum += term;
  return a / 2 * sum;
}

TEST(Interreflections, InsideAShellEachBounceAddsTheGeometricSeries) {
  const Scene scene = shellScene(0.8f, 32);
  const auto constant = makeConstantEnvironment(Rgb::Constant(1));
  for (double cacheCell : {0.0, 1.0 / 256}) {
    for (int bounces = 0; bounces <= 3; ++bounces) {
      const LoadedTransport t = precomputeInMemory(scene, bounceOptions(bounces, cacheCell));
      ASSERT_EQ(t.header.channels, 1) << "grey surfaces keep one row per pixel";
      const auto rows = innerRows(t);
      ASSERT_GT(rows.size(), 300u);
      const double mean = meanOver(test::greyRows(t, *constant), rows);
      const double expected = shellRadiance(0.8, bounces);
      EXPECT_NEAR(mean / expected, 1.0, 0.01)
          << "K " << bounces << " cache " << cacheCell << ": " << mean << " vs " << expected;
    }
  }
}

TEST(Interreflections, LightFromBelowTheRimNeverReachesInsideTheShell) {
  const Scene scene = shellScene(0.9f, 24);
  const CubeLattice lattice(16);
  LatticeLighting below(3 * lattice.size(), 0.0);
  for (int j = 0; j < lattice.size(); ++j)
    if (lattice.direction(j).y() < 0)
      for (int c = 0; c < 3; ++c) below[3 * j + c] = lattice.solidAngle(j);
  for (double cacheCell : {0.0, 1.0 / 256})
    for (int bounces : {0, 1, 3}) {
      const LoadedTransport t = precomputeInMemory(scene, bounceOptions(bounces, cacheCell));
      for (long long r : innerRows(t)) {
        double value = 0;
        for (int j = 0; j < lattice.size(); ++j) value += double(t.row(r)[j]) * below[3 * j];
        ASSERT_EQ(value, 0.0) << "row " << r << " K " << bounces << " cache " << cacheCell;
      }
    }
}

/// An open corner: a floor and a wall of albedo 1 meeting at a right angle.
/// No point sees more than half of its cosine-weighted view taken by the other.
Scene furnaceCorner(int size) {
  Scene s{"corner", {}, {}, {}, {}, {}};
  s.camera.eye = {0, 1.6, 2.6};
  s.camera.target = {0, 0.5, -0.5};
  s.camera.fovDegrees = 40;
  s.camera.size = {size, size};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 2, grey(1), "floor"));
  s.meshes.push_back(makeQuad({0, 1, -1}, {0, 0, 1}, 2, grey(1), "wall"));
  return s;
}

TEST(Interreflections, WhiteFurnaceTendsToOneWithin_HalfToTheKPlusOne) {
  const Scene scene = furnaceCorner(20);
  const auto constant = makeConstantEnvironment(Rgb::Constant(1));
  std::vector<double> previous;
  for (int bounces = 0; bounces <= 3; ++bounces) {
    PrecomputeOptions o = bounceOptions(bounces, 1.0 / 512);
    o.indirectSamples = 1024;
    const LoadedTransport t = precomputeInMemory(scene, o);
    const auto b = test::greyRows(t, *constant);
    const double bound = std::pow(0.5, bounces + 1);
    // The lattice's horizon texels (about 1%) and the paths' noise (under 3%
    // per pixel at 1024 paths).
    const double slack = 0.04;
    for (size_t r = 0; r < b.size(); ++r) {
      ASSERT_GE(b[r], 1 - bound - slack) << "row " << r << " K " << bounces;
      ASSERT_LE(b[r], 1 + slack) << "row " << r << " K " << bounces;
    }
    if (!previous.empty()) {
      double gained = 0;
      for (size_t r = 0; r < b.size(); ++r) gained += b[r] - previous[r];
      EXPECT_GT(gained / b.size(), 0.001) << "K " << bounces << " adds light";
    }
    previous = b;
  }
}

TEST(Interreflections, NothingElseToBounceOffGivesTheDirectRowsExactly) {
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = {20, 20};
  const LoadedTransport direct = precomputeInMemory(scene, bounceOptions(0, 0, 8));
  for (double cacheCell : {0.0, 1.0 / 256}) {
    const LoadedTransport bounced = precomputeInMemory(scene, bounceOptions(3, cacheCell, 8));
    EXPECT_EQ(bounced.header.bounces, 3);
    EXPECT_EQ(bounced.rows, direct.rows) << "a convex object alone: every path escapes";
    EXPECT_EQ(bounced.stats.cachePoints, 0);
  }
}

TEST(Interreflections, MoreBouncesNeverDarkenAnyValue) {
  Scene scene = makePlantScene();
  scene.camera.size = {16, 16};
  std::vector<float> previous;
  for (int bounces = 0; bounces <= 3; ++bounces) {
    PrecomputeOptions o = bounceOptions(bounces, 0, 8);
    o.indirectSamples = 8;
    const LoadedTransport t = precomputeInMemory(scene, o);
    if (bounces > 0) {
      ASSERT_EQ(t.header.channels, 3) << "the plant's surfaces are coloured";
      ASSERT_EQ(t.rows.size(), previous.size() * (bounces == 1 ? 3 : 1));
      const int l = t.directions;
      double added = 0;
      for (long long r = 0; r < t.header.rows(); ++r)
        for (int c = 0; c < 3; ++c)
          for (int j = 0; j < l; ++j) {
            // K = 0's rows are shared by the three channels.
            const float before = bounces == 1 ? previous[r * l + j] : previous[(r * 3 + c) * l + j];
            const float now = t.part(r, c)[j];
            ASSERT_GE(now, before) << "row " << r << " channel " << c << " texel " << j;
            added += now - before;
          }
      EXPECT_GT(added, 0) << "K " << bounces;
    }
    previous = t.rows;
  }
}

TEST(Interreflections, BouncedLightCarriesTheColourItBouncedOff) {
  // A white sphere on a red floor: its lower half turns red under white light.
  Scene scene{"bleed", {}, {}, {}, {}, {}};
  scene.camera.eye = {0, 1.2, 4};
  scene.camera.target = {0, 0.8, 0};
  scene.camera.fovDegrees = 30;
  scene.camera.size = {24, 24};
  scene.meshes.push_back(
      makeQuad({0, 0, 0}, {0, 1, 0}, 8, {Material::Type::Diffuse, {0.8f, 0.1f, 0.1f}}, "floor"));
  scene.spheres.push_back({{0, 1, 0}, 0.8, grey(0.9f)});
  const LoadedTransport t = precomputeInMemory(scene, bounceOptions(1, 1.0 / 256, 8));
  ASSERT_EQ(t.header.channels, 3);
  const CubeLattice lattice(8);
  const LatticeLighting white =
      computeLighting(*makeConstantEnvironment(Rgb::Constant(1)), lattice, {});
  int lowerSphere = 0;
  for (long long r = 0; r < t.header.rows(); ++r) {
    if (t.header.albedo[3 * r + 1] < 0.5f || t.header.normals[3 * r + 1] > -0.3f) continue;
    double red = 0, green = 0;
    for (int j = 0; j < lattice.size(); ++j) {
      red += double(t.part(r, 0)[j]) * white[3 * j];
      green += double(t.part(r, 1)[j]) * white[3 * j + 1];
    }
    EXPECT_GT(red, 1.2 * green) << "row " << r;
    ++lowerSphere;
  }
  EXPECT_GT(lowerSphere, 5);
}

TEST(Interreflections, RowsDoNotDependOnTheThreadCount) {
  Scene scene = makePlantScene();
  scene.camera.size = {20, 20};
  PrecomputeOptions o = bounceOptions(2, 1.0 / 512, 8);
  o.indirectSamples = 16;
  o.threads = 1;
  const LoadedTransport one = precomputeInMemory(scene, o);
  o.threads = 3;
  const LoadedTransport three = precomputeInMemory(scene, o);
  EXPECT_EQ(one.rows, three.rows);
  EXPECT_EQ(one.stats.cachePoints, three.stats.cachePoints);
}

TEST(Interreflections, AbsurdSettingsAreRefused) {
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = {4, 4};
  test::TempDir dir;
  const auto refuse = [&](PrecomputeOptions o) {
    EXPECT_THROW(precomputeTransport(scene, dir.file("x.h5"), o), UserError);
  };
  PrecomputeOptions o = bounceOptions(1, 0, 4);
  o.bounces = -1, refuse(o);
  o.bounces = kMaxBounces + 1, refuse(o);
  o = bounceOptions(1, 0, 4);
  o.indirectSamples = 0, refuse(o);
  o.indirectSamples = kMaxIndirectSamples + 1, refuse(o);
  o = bounceOptions(1, 0, 4);
  o.indirectCacheCell = -1, refuse(o);
  o.indirectCacheCell = std::nan(""), refuse(o);
}

}  // namespace
}  // namespace acpca
