// A real sky's sun through the CLI (issue: all-frequency under real skies):
// a sphere on a plane, 96x96, under a 4096x2048 map of a smooth sky and a
// 0.53-degree sun. The reference is the same sky without the sun plus the sun
// as an exact `sphere:` lamp 1000 units away, of the solid angle the map's
// own pixels give it and their radiance, at 256 rays. The default relight
// splits the sun off and lights it exactly; `--sun off` keeps it on the
// lattice, as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/error.h"
#include "imageio/image_output.h"
#include "tests/cli/image_pixels.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMapWidth = 4096, kMapHeight = 2048;
constexpr double kSunTheta = 50, kSunPhi = 30, kSunRadius = 0.265, kSunRadiance = 4e4;

Vec3 directionAt(double theta, double phi) {  // docs/lighting.md, "Conventions"
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

/// A smooth sky: blue at the zenith, paler at the horizon, a dim ground.
Rgb skyRadiance(const Vec3& d) {
  if (d.y() < 0) return {0.05, 0.05, 0.05};
  const double t = std::pow(1 - d.y(), 3);
  return (1 - t) * Rgb(0.06, 0.10, 0.20) + t * Rgb(0.16, 0.17, 0.19);
}

/// The sun's disc, its pixels' coverage found on 8x8 points each.
struct SkyMaps {
  Image sky, skyAndSun;
  Vec3 sunDirection = Vec3::Zero();  ///< the coverage-weighted centre
  double sunSolidAngle = 0;          ///< its pixels' solid angle x coverage
  Rgb sunRadiance = Rgb::Zero();     ///< over the sky beneath it
};

SkyMaps makeSkyMaps() {
  SkyMaps m;
  m.sky = {kMapWidth, kMapHeight, 3, std::vector<float>(3ull * kMapWidth * kMapHeight)};
  m.skyAndSun = m.sky;
  const Vec3 sun = directionAt(kSunTheta * kPi / 180, kSunPhi * kPi / 180);
  const double cosRadius = std::cos(kSunRadius * kPi / 180);
  Rgb excess = Rgb::Zero();
  for (int y = 0; y < kMapHeight; ++y) {
    const double rowOmega =
        (std::cos(kPi * y / kMapHeight) - std::cos(kPi * (y + 1) / kMapHeight)) * 2 * kPi /
        kMapWidth;
    for (int x = 0; x < kMapWidth; ++x) {
      const auto angles = [&](double fx, double fy) {
        return directionAt(kPi * (y + fy) / kMapHeight, 2 * kPi * ((x + fx) / kMapWidth - 0.5));
      };
      const Vec3 centre = angles(0.5, 0.5);
      const Rgb sky = skyRadiance(centre);
      double cover = 0;
      if (centre.dot(sun) > std::cos((kSunRadius + 0.2) * kPi / 180))
        for (int k = 0; k < 64; ++k)
          cover += angles((k % 8 + 0.5) / 8, (k / 8 + 0.5) / 8).dot(sun) >= cosRadius ? 1. / 64 : 0;
      const size_t i = 3 * (static_cast<size_t>(y) * kMapWidth + x);
      for (int c = 0; c < 3; ++c) {
        m.sky.pixels[i + c] = static_cast<float>(sky[c]);
        m.skyAndSun.pixels[i + c] = static_cast<float>(cover * kSunRadiance + (1 - cover) * sky[c]);
      }
      if (cover > 0) {
        for (int c = 0; c < 3; ++c)
          excess[c] += rowOmega * (double(m.skyAndSun.pixels[i + c]) - m.sky.pixels[i + c]);
        m.sunSolidAngle += rowOmega * cover;
        m.sunDirection += rowOmega * cover * centre;
      }
    }
  }
  m.sunDirection.normalize();
  m.sunRadiance = excess / m.sunSolidAngle;
  return m;
}

/// Relative L2 of a against r over every value, or over the pixels `mask` holds.
double relativeL2(const std::vector<float>& a, const std::vector<float>& r,
                  const std::vector<bool>& mask = {}) {
  double err = 0, norm = 0;
  for (size_t i = 0; i < r.size(); ++i) {
    if (!mask.empty() && !mask[i / 3]) continue;
    err += std::pow(double(a[i]) - r[i], 2), norm += std::pow(double(r[i]), 2);
  }
  return std::sqrt(err / norm);
}

/// The pixels within 2 px of a shadow edge of the sun-only frame: where
/// green falls by more than half from one pixel to the next.
std::vector<bool> nearShadowEdges(const std::vector<float>& sunOnly, int width, int height) {
  std::vector<bool> edge(static_cast<size_t>(width) * height, false), near = edge;
  const auto g = [&](int x, int y) { return double(sunOnly[3 * (size_t(y) * width + x) + 1]); };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (x + dx >= width || y + dy >= height) continue;
        const double a = g(x, y), b = g(x + dx, y + dy);
        if (std::abs(a - b) > 0.5 * std::max(a, b))
          edge[size_t(y) * width + x] = edge[size_t(y + dy) * width + x + dx] = true;
      }
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (edge[size_t(y) * width + x])
        for (int ny = std::max(0, y - 2); ny <= std::min(height - 1, y + 2); ++ny)
          for (int nx = std::max(0, x - 2); nx <= std::min(width - 1, x + 2); ++nx)
            near[size_t(ny) * width + nx] = true;
  return near;
}

TEST(MapSun, ASkysSunIsLitAsItsExactDiscFromTransportAndModel) {
  const test::TempDir dir;
  {
    std::ofstream scene(dir.file("scene.json"));
    scene << R"({"name": "sun-on-sphere",
      "camera": {"eye": [0, 3.2, 3.2], "target": [0, 0.3, 0], "up": [0, 1, 0], "fov": 40,
                 "width": 96, "height": 96},
      "objects": [
        {"shape": "plane", "center": [0, 0, 0], "normal": [0, 1, 0], "size": 8,
         "material": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]}},
        {"shape": "sphere", "center": [-0.2, 0.6, -0.2], "radius": 0.6,
         "material": {"type": "diffuse", "albedo": [0.6, 0.5, 0.4]}}]})";
  }
  const SkyMaps maps = makeSkyMaps();
  writeImage(maps.sky, dir.file("sky.exr"), ImageFormat::Exr, 0, true);
  writeImage(maps.skyAndSun, dir.file("sun.exr"), ImageFormat::Exr, 0, true);
  const std::string t = dir.file("t.h5"), m = dir.file("m.h5");
  ASSERT_EQ(runCli(concat("precompute -q --scene ", dir.file("scene.json"),
                          " --spp 4 --aa full --out ", t))
                .status,
            0);
  ASSERT_EQ(runCli(concat("compress -q ", t, " --method adaptive-quad --out ", m)).status, 0);
  const auto frame = [&](const std::string& input, const std::string& args,
                         const std::string& name) {
    const RunResult r =
        runCli(concat("relight -q ", input, " --background black --exr-float ", args, " --out ",
                      dir.file(name), " --json ", dir.file(name + ".json")));
    EXPECT_EQ(r.status, 0) << r.output;
    return test::readPixels(dir.file(name));
  };
  // The sun as a sphere lamp 1000 units away, of the pixels' solid angle.
  const double alpha = std::acos(1 - maps.sunSolidAngle / (2 * kPi));
  const Vec3 at = 1000 * maps.sunDirection;
  const std::string lamp =
      concat("sphere:", at.x(), ",", at.y(), ",", at.z(), ",", 1000 * std::sin(alpha), ",",
             maps.sunRadiance.x(), ",", maps.sunRadiance.y(), ",", maps.sunRadiance.z());
  const std::vector<float> reference =
      frame(t, concat("--env ", dir.file("sky.exr"), " --light ", lamp, " --lamp-rays 256"),
            "reference.exr");
  const std::vector<float> sunOnly =
      frame(t, concat("--env constant:0 --light ", lamp, " --lamp-rays 256"), "sun_only.exr");
  const std::vector<bool> edges = nearShadowEdges(sunOnly, 96, 96);
  ASSERT_GT(std::count(edges.begin(), edges.end(), true), 200);
  const std::string env = "--env " + dir.file("sun.exr");
  const std::vector<float> exact = frame(t, env, "exact.exr");
  const std::vector<float> lattice = frame(t, env + " --sun off", "lattice.exr");
  const std::vector<float> model = frame(m, env, "model.exr");
  const std::vector<float> modelLattice = frame(m, env + " --sun off", "model_lattice.exr");
  ASSERT_EQ(exact.size(), reference.size());
  const struct {
    const char* name;
    const std::vector<float>& frame;
    double overall, nearEdges;  // bounds; 0: measured only
  } cases[] = {{"transport", exact, 0.015, 0.03},
               {"transport --sun off", lattice, 0, 0},
               {"adaptive-quad", model, 0.03, 0.05},
               {"adaptive-quad --sun off", modelLattice, 0, 0}};
  for (const auto& c : cases) {
    const double all = relativeL2(c.frame, reference), near = relativeL2(c.frame, reference, edges);
    if (c.overall > 0) {
      EXPECT_LT(all, c.overall) << c.name;
      EXPECT_LT(near, c.nearEdges) << c.name;
    }
    RecordProperty(concat(c.name, " relative_l2"), std::to_string(all));
    RecordProperty(concat(c.name, " relative_l2_near_edges"), std::to_string(near));
  }
  // The exact sun is closer than the lattice's, near edges by far.
  EXPECT_LT(relativeL2(exact, reference, edges), 0.5 * relativeL2(lattice, reference, edges));
  // The report lists the sun found: its direction, size and share.
  std::ifstream in(dir.file("exact.exr.json"));
  const nlohmann::json report = nlohmann::json::parse(in);
  ASSERT_EQ(report.at("sources").size(), 1u);
  const nlohmann::json& found = report.at("sources")[0].at("sources")[0];
  EXPECT_NEAR(found.at("theta_deg").get<double>(), kSunTheta, 0.05);
  EXPECT_NEAR(found.at("phi_deg").get<double>(), kSunPhi, 0.05);
  EXPECT_NEAR(found.at("radius_deg").get<double>(), kSunRadius, 0.01);
  EXPECT_GT(found.at("energy_share").get<double>(), 0.5);
}

}  // namespace
}  // namespace acpca
