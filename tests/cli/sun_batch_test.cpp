// A map's sources in the CLI's batches (docs/lighting.md, "Lit exactly"):
// turned with each frame, listed in the manifest and in sh9, the same as the
// lattice's light, refused flags named, and files that cannot light them
// exactly falling back to the lattice with one warning naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "tests/cli/image_pixels.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

class SunBatch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    for (const auto& [name, flags] :
         {std::pair{"step.h5", ""}, std::pair{"bounced.h5", " --bounces 1 --indirect-samples 4"}}) {
      const RunResult r =
          runCli("precompute --scene step --size 48x48 -q --out " + dir_->file(name) + flags);
      ASSERT_EQ(r.status, 0) << r.output;
    }
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string file(const std::string& name) { return dir_->file(name); }
  static std::vector<nlohmann::json> manifest(const std::string& directory) {
    std::vector<nlohmann::json> lines;
    std::ifstream in(directory + "/manifest.jsonl");
    for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
    return lines;
  }
  static test::TempDir* dir_;
};
test::TempDir* SunBatch::dir_ = nullptr;

double sum(const std::vector<float>& values) {
  double s = 0;
  for (float v : values) s += v;
  return s;
}

TEST_F(SunBatch, ASweepTurnsTheSunListsItAndKeepsTheLatticesLight) {
  // `sun:` alone is all source: a yaw sweep's manifest lists it turned, its
  // sh9 is the closed form's, and each frame holds about the light the
  // lattice gave it.
  const std::string env = " --env sun:40,30,0.53,40000 --rotate 0:360:90 --background black";
  for (const char* sun : {"auto", "off"}) {
    const RunResult r = runCli(concat("relight ", file("step.h5"), env, " --sun ", sun,
                                      " --exr-float -q --out ", file(concat("sweep_", sun))));
    ASSERT_EQ(r.status, 0) << r.output;
  }
  const auto exact = manifest(file("sweep_auto")), lattice = manifest(file("sweep_off"));
  ASSERT_EQ(exact.size(), 4u);
  for (size_t k = 0; k < exact.size(); ++k) {
    SCOPED_TRACE(k);
    ASSERT_EQ(exact[k].at("sources").size(), 1u);
    EXPECT_TRUE(lattice[k].at("sources").empty());
    const nlohmann::json& s = exact[k].at("sources")[0];
    EXPECT_NEAR(s.at("theta_deg").get<double>(), 40, 1e-9);
    // A yaw of Y degrees takes PHI to PHI - Y.
    EXPECT_NEAR(std::remainder(s.at("phi_deg").get<double>() - (30 - 90.0 * k), 360), 0, 1e-9);
    EXPECT_NEAR(s.at("radius_deg").get<double>(), 0.265, 1e-9);
    // sh9 bands 0 and 1 in closed form: L Y(d) times 2 pi (1 - cos a) and
    // pi sin^2 a, Y(0,0) = 1 / (2 sqrt(pi)), Y(1,m) = sqrt(3 / 4 pi) (y, z, x).
    const double a = 0.265 * std::numbers::pi / 180, pi = std::numbers::pi;
    const nlohmann::json& d = s.at("direction");
    const double band0 = 4e4 * 2 * pi * (1 - std::cos(a)) / (2 * std::sqrt(pi));
    const double band1 = 4e4 * pi * std::sin(a) * std::sin(a) * std::sqrt(3 / (4 * pi));
    const double expected[4] = {band0, band1 * d[1].get<double>(), band1 * d[2].get<double>(),
                                band1 * d[0].get<double>()};
    for (int band = 0; band < 4; ++band)
      EXPECT_NEAR(exact[k]["sh9"][band][1].get<double>(), expected[band], 1e-9 * band0) << band;
    // ... and every band near the lattice's, which moves the sun to a texel's centre.
    for (int band = 0; band < 9; ++band)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(exact[k]["sh9"][band][c].get<double>(),
                    lattice[k]["sh9"][band][c].get<double>(),
                    0.03 * std::abs(exact[k]["sh9"][0][c].get<double>()))
            << band;
    const std::string name = exact[k].at("outputs")[0];
    const double lit = sum(test::readPixels(file("sweep_auto/" + name)));
    const double onLattice = sum(test::readPixels(file("sweep_off/" + name)));
    EXPECT_GT(lit, 0);
    // The lattice moves the sun up to 1.4 degrees: cos(40 +- 1.4) is 2% off, its shadow moves.
    EXPECT_NEAR(lit / onLattice, 1, 0.05);
  }
}

TEST_F(SunBatch, OffAndTheLatticeLightModeGiveTheSameBytes) {
  const auto frame = [&](const std::string& flags, const std::string& name) {
    const RunResult r =
        runCli(concat("relight ", file("step.h5"), " --env sky", flags, " -q --out ", file(name)));
    EXPECT_EQ(r.status, 0) << r.output;
    return test::readPixels(file(name));
  };
  const std::vector<float> off = frame(" --sun off", "off.exr");
  EXPECT_EQ(frame(" --light-mode lattice", "lattice.exr"), off);
  EXPECT_NE(frame("", "exact.exr"), off);
}

TEST_F(SunBatch, AFileWithBouncedLightKeepsTheSunOnTheLatticeWithOneWarning) {
  const std::string base = concat("relight ", file("bounced.h5"), " --env sky --rotate 0:360:180");
  const RunResult warned = runCli(base + " --out " + file("bounced_auto"));
  ASSERT_EQ(warned.status, 0) << warned.output;
  const std::string words = "the maps' suns and bright lamps go through the lattice";
  const size_t at = warned.output.find(words);
  ASSERT_NE(at, std::string::npos) << warned.output;
  EXPECT_EQ(warned.output.find(words, at + 1), std::string::npos) << "once";
  EXPECT_NE(warned.output.find(file("bounced.h5")), std::string::npos);
  const RunResult quiet = runCli(base + " --sun off --out " + file("bounced_off"));
  ASSERT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find(words), std::string::npos);
  const auto a = manifest(file("bounced_auto")), b = manifest(file("bounced_off"));
  ASSERT_EQ(a.size(), 2u);
  for (size_t k = 0; k < a.size(); ++k) {
    const std::string name = a[k].at("outputs")[0];
    EXPECT_EQ(test::readPixels(file("bounced_auto/" + name)),
              test::readPixels(file("bounced_off/" + name)));
    EXPECT_TRUE(a[k].at("sources").empty());
  }
}

TEST_F(SunBatch, EveryMethodsModelIsNoFartherFromItsTransportUnderAnExactSun) {
  // The sun's light does not pass through a model's rows: each method's frame
  // differs from the transport's only in the sky, so by about no more than
  // when the lattice carries the sun through the compression too.
  const auto frame = [&](const std::string& input, const std::string& flags,
                         const std::string& name) {
    const RunResult r = runCli(concat("relight ", input, " --env sky --background black", flags,
                                      " --exr-float -q --out ", file(name)));
    EXPECT_EQ(r.status, 0) << r.output;
    return test::readPixels(file(name));
  };
  const auto relativeL2 = [](const std::vector<float>& a, const std::vector<float>& b) {
    double e = 0, n = 0;
    for (size_t i = 0; i < b.size(); ++i) e += std::pow(a[i] - b[i], 2), n += b[i] * b[i];
    return std::sqrt(e / n);
  };
  // A 6x16x16 lattice: the sun is lit off the lattice whatever its size, and
  // five compressions of it take 7 s on two cores against 32 s at 6x32x32.
  const std::string step = file("step16.h5");
  ASSERT_EQ(runCli("precompute --scene step --size 48x48 --cubemap 16 -q --out " + step).status, 0);
  const std::vector<float> dense = frame(step, "", "dense.exr");
  const std::vector<float> denseOff = frame(step, " --sun off", "dense_off.exr");
  for (const char* method : {"global", "block", "cpca", "adaptive-binary", "adaptive-quad"}) {
    SCOPED_TRACE(method);
    const std::string model = file(concat(method, ".h5"));
    const RunResult r =
        runCli(concat("compress ", step, " --method ", method, " -q --out ", model));
    ASSERT_EQ(r.status, 0) << r.output;
    const double exact = relativeL2(frame(model, "", "m.exr"), dense);
    const double lattice = relativeL2(frame(model, " --sun off", "m_off.exr"), denseOff);
    // Not strictly: the sky's error and the sun's through the lattice may
    // cancel in part (measured up to 2.5% the other way, block and CPCA).
    EXPECT_LE(exact, lattice * 1.05) << exact << " against " << lattice;
    RecordProperty(concat(method, " exact lattice"), concat(exact, " ", lattice));
  }
}

TEST_F(SunBatch, ASunFlagThatIsNotAutoOffOrACountIsRefusedNamingIt) {
  for (const char* bad : {"maybe", "0", "-1", "2.5"})
    expectFailure(
        concat("relight ", file("step.h5"), " --env sky --sun '", bad, "' --out ", file("x.exr")),
        concat("--sun '", bad, "'"));
}

}  // namespace
}  // namespace acpca
