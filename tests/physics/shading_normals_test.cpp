// Shading normals: a tessellated sphere shaded with interpolated normals must
// look like the true sphere, and the rule for light that arrives above the
// shading horizon but below the geometric one must cost almost nothing on a
// smooth convex mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "precompute/scene.h"
#include "tests/physics/grey_rows.h"
#include "tests/render_support.h"

namespace acpca {
namespace {

using test::LoadedTransport;
using test::precomputeInMemory;

constexpr double kPi = std::numbers::pi;

/// A UV sphere of unit radius at the origin: `segments` around, `rings` from
/// pole to pole, with fans at the poles (no zero-area triangles).
TriangleMesh uvSphere(int segments, int rings, const Material& material) {
  TriangleMesh m = emptyMesh("uv-sphere", material);
  m.vertices.emplace_back(0.0f, 1.0f, 0.0f);  // north pole
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = kPi * r / rings, phi = 2 * kPi * s / segments;
      m.vertices.emplace_back(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                              float(std::sin(theta) * std::sin(phi)));
    }
  m.vertices.emplace_back(0.0f, -1.0f, 0.0f);  // south pole
  const int south = static_cast<int>(m.vertices.size()) - 1;
  const auto at = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) {
    m.triangles.emplace_back(0, at(1, s + 1), at(1, s));
    m.triangles.emplace_back(south, at(rings - 1, s), at(rings - 1, s + 1));
    for (int r = 1; r + 1 < rings; ++r) {
      m.triangles.emplace_back(at(r, s), at(r, s + 1), at(r + 1, s));
      m.triangles.emplace_back(at(r, s + 1), at(r + 1, s + 1), at(r + 1, s));
    }
  }
  return m;
}

/// The built-in sphere scene with its analytic sphere replaced by a mesh.
Scene meshSphereScene(NormalMode normals) {
  Scene scene = makeBuiltinScene("sphere");
  scene.camera.size = {64, 64};
  TriangleMesh mesh = uvSphere(48, 24, scene.spheres[0].material);
  if (normals == NormalMode::Smooth) smoothNormals(mesh);
  scene.spheres.clear();
  scene.meshes.push_back(std::move(mesh));
  return scene;
}

/// Grey value of every pixel (index y * width + x; NAN for background).
std::vector<double> relitPixels(const LoadedTransport& t, const Environment& env) {
  const std::vector<double> rows = test::greyRows(t, env);
  std::vector<double> out(t.header.camera.size.pixels(), NAN);
  for (long long r = 0; r < t.header.rows(); ++r) out[t.header.pixels[r]] = rows[r];
  return out;
}

/// Pixels with every pixel within `margin` covered in both images.
std::vector<int> interiorPixels(const std::vector<double>& a, const std::vector<double>& b,
                                int width, int margin) {
  std::vector<int> out;
  const int height = static_cast<int>(a.size()) / width;
  for (int y = margin; y < height - margin; ++y)
    for (int x = margin; x < width - margin; ++x) {
      bool inside = true;
      for (int dy = -margin; dy <= margin && inside; ++dy)
        for (int dx = -margin; dx <= margin && inside; ++dx) {
          const int p = (y + dy) * width + x + dx;
          inside = !std::isnan(a[p]) && !std::isnan(b[p]);
        }
      if (inside) out.push_back(y * width + x);
    }
  return out;
}

double relativeL2Over(const std::vector<double>& b, const std::vector<double>& ref,
                      const std::vector<int>& pixels) {
  double diff = 0, norm = 0;
  for (int p : pixels) diff += (b[p] - ref[p]) * (b[p] - ref[p]), norm += ref[p] * ref[p];
  return std::sqrt(diff / norm);
}

PrecomputeOptions lattice16() {
  PrecomputeOptions o;
  o.cubemapResolution = 16;
  o.precision = Precision::F32;
  return o;
}

TEST(ShadingNormals, SmoothUvSphereUnderASunMatchesTheAnalyticSphere) {
  Scene analytic = makeBuiltinScene("sphere");
  analytic.camera.size = {64, 64};
  const auto sun = makeSunEnvironment(60, 120, 6, Rgb::Constant(300));
  const auto truth = relitPixels(precomputeInMemory(analytic, lattice16()), *sun);
  const auto smooth =
      relitPixels(precomputeInMemory(meshSphereScene(NormalMode::Smooth), lattice16()), *sun);
  const auto flat =
      relitPixels(precomputeInMemory(meshSphereScene(NormalMode::Flat), lattice16()), *sun);
  const auto pixels = interiorPixels(truth, smooth, 64, 2);
  ASSERT_GT(pixels.size(), 1000u);
  const double smoothError = relativeL2Over(smooth, truth, pixels);
  const double flatError = relativeL2Over(flat, truth, pixels);
  EXPECT_LT(smoothError, 0.02);
  // The facets show without shading normals: the test can tell the difference.
  EXPECT_GT(flatError, 2 * smoothError);
  RecordProperty("smooth_error", std::to_string(smoothError));
  RecordProperty("flat_error", std::to_string(flatError));
}

TEST(ShadingNormals, SmoothUvSphereKeepsTheFurnaceValueUnderConstantLight) {
  const auto b = relitPixels(precomputeInMemory(meshSphereScene(NormalMode::Smooth), lattice16()),
                             *makeConstantEnvironment(Rgb::Constant(1)));
  // Albedo 0.5 under constant 1 gives 0.5 wherever the whole hemisphere is
  // open; the geometric-horizon rule drops the thin wedge between the shading
  // and the geometric horizon, a fraction of about (angle between them)^2 / 2.
  int counted = 0;
  double worst = 0;
  for (double v : b)
    if (!std::isnan(v)) ++counted, worst = std::max(worst, std::abs(v - 0.5) / 0.5);
  ASSERT_GT(counted, 1000);
  EXPECT_LT(worst, 0.01);
}

TEST(ShadingNormals, CreasesStaySharpAndFileModesParse) {
  // A box: every edge is 90 degrees, sharper than the default crease angle,
  // so smooth normals are the face normals.
  TriangleMesh box = makeBox({0, 0, 0}, {1, 1, 1}, Material{}, "box");
  smoothNormals(box);
  ASSERT_EQ(box.normals.size(), 3 * box.triangles.size());
  for (size_t t = 0; t < box.triangles.size(); ++t) {
    const auto& tri = box.triangles[t];
    const Eigen::Vector3f face = (box.vertices[tri[1]] - box.vertices[tri[0]])
                                     .cross(box.vertices[tri[2]] - box.vertices[tri[0]])
                                     .normalized();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(box.normals[3 * t + k].dot(face), 1, 1e-6);
  }
  // Above 90 degrees the corners are shared by three faces: (1,1,1)/sqrt(3).
  smoothNormals(box, 100);
  EXPECT_NEAR(std::abs(box.normals[0].x()), 1 / std::sqrt(3.0f), 1e-6);
  EXPECT_EQ(kNormalModeNames.parse("smooth"), NormalMode::Smooth);
  // Zero-area triangles (real files have them) still get unit normals.
  TriangleMesh sliver = emptyMesh("sliver", Material{});
  sliver.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 0, 1}};
  sliver.triangles = {{0, 1, 2}, {0, 3, 1}};
  smoothNormals(sliver);
  for (const auto& n : sliver.normals) EXPECT_NEAR(n.norm(), 1, 1e-6);
  EXPECT_NO_THROW(Scene({"s", {}, {sliver}, {}, {}, {}}).validate());
  EXPECT_THROW(kNormalModeNames.parse("phong"), ParameterError);
}

}  // namespace
}  // namespace acpca
