// Local lights: the grammar, and what each light adds to the lattice lighting
// at a point, against closed forms (inverse square, a sphere's solid angle)
// and brute-force integration over the texels.
#include "lighting/local_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>

#include "core/error.h"
#include "lighting/rotation.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

double sumOf(const std::vector<LightTap>& taps) {
  double s = 0;
  for (const auto& t : taps) s += t.weight;
  return s;
}

std::map<int, double> byTexel(const std::vector<LightTap>& taps) {
  std::map<int, double> m;
  for (const auto& t : taps) m[t.texel] += t.weight;
  return m;
}

/// Each spec refused by `read` as a ParameterError ("light") naming the spec
/// and saying the problem.
void expectRefused(const std::function<void(const std::string&)>& read,
                   const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [spec, problem] : cases) {
    try {
      read(spec);
      ADD_FAILURE() << spec << " was accepted";
    } catch (const ParameterError& e) {
      EXPECT_EQ(e.parameter(), "light");
      EXPECT_EQ(e.value(), spec);
      EXPECT_NE(e.problem().find(problem), std::string::npos) << spec << ": " << e.what();
    }
  }
}

TEST(LocalLightSpec, EveryKindParsesGreyAndRgbAndPrintsBack) {
  const LocalLight p = parseLocalLight("point:1,2,-3,5");
  EXPECT_STREQ(p.kindName(), "point");
  EXPECT_EQ(p.position, Vec3(1, 2, -3));
  EXPECT_EQ(p.emission, Rgb(5, 5, 5));
  EXPECT_EQ(p.canonicalSpec(), "point:1,2,-3,5");
  const LocalLight s = parseLocalLight("sphere:0,4,0,0.5,10,20,30");
  EXPECT_STREQ(s.kindName(), "sphere");
  ASSERT_TRUE(s.as<SphereLight>());
  EXPECT_EQ(s.as<SphereLight>()->radius, 0.5);
  EXPECT_FALSE(s.as<SpotLight>()) << "a sphere has no axis";
  EXPECT_EQ(s.emission, Rgb(10, 20, 30));
  EXPECT_EQ(parseLocalLight(s.canonicalSpec()).canonicalSpec(), s.canonicalSpec());
  const LocalLight spot = parseLocalLight("spot:0,3,0,0,-2,0,30,7");
  EXPECT_STREQ(spot.kindName(), "spot");
  ASSERT_TRUE(spot.as<SpotLight>());
  EXPECT_EQ(spot.as<SpotLight>()->axis, Vec3(0, -1, 0)) << "the direction is normalised";
  EXPECT_EQ(spot.as<SpotLight>()->halfAngleDegrees, 30);
  EXPECT_EQ(spot.canonicalSpec(), "spot:0,3,0,0,-1,0,30,7");
}

TEST(LocalLightSpec, BadSpecsAreRefusedNamingTheSpecAndTheProblem) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"point", "KIND:NUMBERS"},
      {"lamp:1,2,3,4", "'lamp' is not one of point, sphere, spot"},
      {"point:1,2,3", "has 3 numbers"},
      {"point:1,2,3,4,5", "has 5 numbers"},
      {"sphere:0,1,0,1", "has 4 numbers"},
      {"spot:0,1,0,0,-1,0,30", "has 7 numbers"},
      {"point:1,x,3,4", "'x' is not a finite number"},
      {"point:1,2,nan,4", "'nan' is not a finite number"},
      {"point:1,2,3,inf", "'inf' is not a finite number"},
      {"point:1,2,3,-1", "intensity must be finite and in [0, 1e+20]"},
      {"point:1,2,3,1,-2,1", "intensity must be finite and in [0, 1e+20]"},
      {"point:1,2,3,1e21", "intensity must be finite and in [0, 1e+20]"},
      {"point:1e16,2,3,1", "position must be finite, within +-1e+15"},
      {"sphere:0,1,0,0,5", "radius must be finite and in (0, 1e+15]"},
      {"sphere:0,1,0,-1,5", "radius must be finite and in (0, 1e+15]"},
      {"sphere:0,1,0,1,-5", "radiance must be finite and in [0, 1e+20]"},
      {"spot:0,1,0,0,0,0,30,1", "direction DX,DY,DZ is zero"},
      {"spot:0,1,0,0,-1,0,0,1", "half angle must be in (0, 90]"},
      {"spot:0,1,0,0,-1,0,91,1", "half angle must be in (0, 90]"},
      {"point:1,,3,4", "'' is not a finite number"},
  };
  expectRefused([](const std::string& spec) { parseLocalLight(spec); }, cases);
}

// A sweep A:B:S in place of a number gives A, A + S, ... below B (as
// --rotate's yaw sweep), every combination of several, the last fastest.
TEST(LocalLightSpec, SweepsExpandToEveryCombinationInOrder) {
  EXPECT_EQ(expandLightSweep("point:1,2,3,4"), std::vector<std::string>{"point:1,2,3,4"});
  EXPECT_FALSE(isLightSweep("point:1,2,3,4"));
  EXPECT_TRUE(isLightSweep("point:0:1:0.5,2,3,4"));
  EXPECT_EQ(expandLightSweep("point:-1:1:0.5,2,3,4"),
            (std::vector<std::string>{"point:-1,2,3,4", "point:-0.5,2,3,4", "point:0,2,3,4",
                                      "point:0.5,2,3,4"}));
  const auto grid = expandLightSweep("sphere:0:2:1,1,5:7:1,0.5,10:30:10");
  ASSERT_EQ(grid.size(), 8u);
  EXPECT_EQ(grid.front(), "sphere:0,1,5,0.5,10");
  EXPECT_EQ(grid[1], "sphere:0,1,5,0.5,20") << "the last swept number moves fastest";
  EXPECT_EQ(grid.back(), "sphere:1,1,6,0.5,20");
  // Steps that do not land on B, and values written as the shortest text.
  const auto tenths = expandLightSweep("point:0:0.35:0.1,0,0,1");
  ASSERT_EQ(tenths.size(), 4u);
  EXPECT_EQ(tenths[3], "point:0.30000000000000004,0,0,1");
  for (const std::string& spec : grid) EXPECT_NO_THROW(parseLocalLight(spec)) << spec;
  // A step past B leaves A alone, however wide (fuzzing found one of 2e73).
  EXPECT_EQ(expandLightSweep("point:0:23:2e73,1,2,3"), std::vector<std::string>{"point:0,1,2,3"});
  EXPECT_EQ(expandLightSweep("point:0:1:1,1,2,3"), std::vector<std::string>{"point:0,1,2,3"});

  const std::vector<std::pair<std::string, std::string>> bad{
      {"point:0:1,2,3,4", "'0:1' is not a sweep A:B:S"},
      {"point:0:1:0,2,3,4", "the step must be > 0"},
      {"point:0:1:-1,2,3,4", "the step must be > 0"},
      {"point:1:1:0.5,2,3,4", "the end must exceed the start"},
      {"point:0:x:1,2,3,4", "'x' is not a finite number"},
      {"point:0:1e6:1,0:1:0.1,3,4", "sweeps more than 100000 lights"},
      {"lamp:0:1:0.5,2,3,4", "'lamp' is not one of point, sphere, spot"},
      {"point:0:1:0.5,2,x,4", "'x' is not a finite number"},
      {"spot:0:1:0.5,1,2,3,4,5,6,7,8,9,10", "has 11 numbers; a light has at most 10"},
  };
  expectRefused([](const std::string& spec) { expandLightSweep(spec); }, bad);
}

TEST(LocalLightTaps, APointLightDeliversTheInverseSquareOverItsFourNearestTexels) {
  const CubeLattice lattice(32);
  const LocalLight light = parseLocalLight("point:0.3,2,-0.7,1");
  for (const Vec3& at : {Vec3(0, 0, 0), Vec3(1, 0.5, 2), Vec3(-3, -1, 0.25)}) {
    std::vector<LightTap> taps;
    ASSERT_TRUE(appendLightTaps(light, lattice, at, taps));
    EXPECT_LE(taps.size(), 4u);
    const double d2 = (light.position - at).squaredNorm();
    EXPECT_NEAR(sumOf(taps), 1 / d2, 1e-12 / d2);
    // Each tap is one of the texels around the light's direction.
    const Vec3 dir = (light.position - at).normalized();
    for (const auto& t : taps) EXPECT_GT(lattice.direction(t.texel).dot(dir), std::cos(0.1));
  }
  std::vector<LightTap> taps;
  EXPECT_FALSE(appendLightTaps(light, lattice, light.position, taps)) << "seen from itself";
}

TEST(LocalLightTaps, APointLightMovesSmoothlyAcrossTexels) {
  // Moving by a hundredth of a texel changes the lighting by about a hundredth
  // of its total: no texel pops on or off.
  const CubeLattice lattice(32);
  const double texel = 0.5 * kPi / 32;
  LatticeLighting before =
      localLighting({parseLocalLight("point:0,0,-1,1")}, lattice, Vec3::Zero());
  for (int step = 1; step <= 300; ++step) {
    const double angle = step * 0.01 * texel;
    LocalLight light = parseLocalLight("point:0,0,-1,1");
    light.position = Vec3(std::sin(angle), 0.3 * std::sin(angle), -std::cos(angle));
    light.position /= light.position.norm();
    const LatticeLighting now = localLighting({light}, lattice, Vec3::Zero());
    double change = 0;
    for (size_t i = 0; i < now.size(); i += 3) change += std::abs(now[i] - before[i]);
    ASSERT_LT(change, 0.05) << "step " << step;
    before = now;
  }
}

TEST(LocalLightTaps, ASpotIsAPointLightInsideItsConeAndDarkOutside) {
  const CubeLattice lattice(16);
  const LocalLight spot = parseLocalLight("spot:0,4,0,0,-1,0,30,2");
  const LocalLight point = parseLocalLight("point:0,4,0,2");
  const auto grey = [&](const LocalLight& l, const Vec3& at) {
    const LatticeLighting lighting = localLighting({l}, lattice, at);
    double s = 0;
    for (size_t i = 0; i < lighting.size(); i += 3) s += lighting[i];
    return s;
  };
  // 26 degrees off the axis: inside the inner cone (27 degrees).
  const Vec3 inside(4 * std::tan(26 * kPi / 180), 0, 0);
  EXPECT_NEAR(grey(spot, inside), grey(point, inside), 1e-12);
  EXPECT_EQ(grey(spot, Vec3(4 * std::tan(31 * kPi / 180), 0, 0)), 0.0);
  // Over the outer tenth it falls monotonically.
  double last = 1;  // the share of the point light's
  for (double deg = 27; deg <= 30; deg += 0.25) {
    const double now = grey(spot, Vec3(4 * std::tan(deg * kPi / 180), 0, 0)) /
                       grey(point, Vec3(4 * std::tan(deg * kPi / 180), 0, 0));
    EXPECT_LE(now, last + 1e-12) << deg;
    last = now;
  }
  EXPECT_NEAR(last, 0, 1e-9);
}

/// The solid angle of a cap in each texel by brute force: 64x64 sub-cells of
/// exact solid angle per texel, counted when their centre is inside.
std::map<int, double> bruteForceCap(const CubeLattice& lattice, const Vec3& axis, double cosAlpha) {
  std::map<int, double> m;
  const int res = lattice.resolution(), sub = 64;
  const double step = 2.0 / res, s = step / sub;
  for (int j = 0; j < lattice.size(); ++j) {
    const TexelCoord t = lattice.texelCoord(j);
    if (lattice.direction(j).dot(axis) < std::cos(std::acos(cosAlpha) + 2 * step)) continue;
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const double x = -1 + t.col * step + (b + 0.5) * s, y = -1 + t.row * step + (a + 0.5) * s;
        if (CubeLattice::faceDirection(t.face, x, y).normalized().dot(axis) >= cosAlpha)
          m[j] += CubeLattice::rectangleSolidAngle(x - s / 2, y - s / 2, x + s / 2, y + s / 2);
      }
  }
  return m;
}

TEST(LocalLightTaps, ASphereDeliversItsExactSolidAngleOverTheTexelsItCovers) {
  const CubeLattice lattice(8);
  const double texel = 0.5 * kPi / 8;
  // Discs from a fraction of a texel to many texels, across a face edge and
  // over a cube corner.
  for (const Vec3& centre : {Vec3(0.2, 3, 0.1), Vec3(3, 3.2, 0.4), Vec3(2, 2.1, -2.05)})
    for (double alphaTexels : {0.2, 1.0, 1.7, 3.0, 6.5}) {
      const double d = centre.norm();
      LocalLight light = parseLocalLight("sphere:0,1,0,1,1");
      light.position = centre;
      const double radius = d * std::sin(alphaTexels * texel);
      light.shape = SphereLight{radius};
      std::vector<LightTap> taps;
      ASSERT_TRUE(appendLightTaps(light, lattice, Vec3::Zero(), taps));
      const double cosAlpha = std::sqrt(1 - std::pow(radius / d, 2));
      const double exact = 2 * kPi * (1 - cosAlpha);
      EXPECT_NEAR(sumOf(taps), exact, 1e-12 * exact) << "energy is exact";
      // Texel by texel against brute force: the share of the disc's solid
      // angle that sits in another texel than it should (half the L1
      // difference) is small: at most 1.0% over these cases.
      const auto brute = bruteForceCap(lattice, centre / d, cosAlpha);
      const auto mine = byTexel(taps);
      double misplaced = 0;
      for (const auto& [j, w] : mine) misplaced += std::abs(w - (brute.count(j) ? brute.at(j) : 0));
      for (const auto& [j, w] : brute)
        if (!mine.count(j)) misplaced += w;
      EXPECT_LT(misplaced / 2, 0.015 * exact)
          << "alpha " << alphaTexels << " texels at " << centre.transpose();
    }
}

TEST(LocalLightTaps, APointInsideASphereLightHasNoTaps) {
  const CubeLattice lattice(8);
  std::vector<LightTap> taps;
  EXPECT_FALSE(
      appendLightTaps(parseLocalLight("sphere:0,0,0,1,1"), lattice, Vec3(0.5, 0, 0), taps));
  EXPECT_TRUE(taps.empty());
  EXPECT_THROW(localLighting({parseLocalLight("sphere:0,0,0,1,1")}, lattice, Vec3(0.5, 0, 0)),
               ParameterError);
}

/// The first way of writing a spec ("point:X,Y,Z,I" of "... or ...").
std::string firstForm(const char* grammar) {
  const std::string text = grammar;
  return text.substr(0, text.find(" or "));
}

TEST(LightKinds, EveryKindParsesPrintsBackAndLightsAPointWithSharesSummingToOne) {
  // One example per kind, by its name: a kind added to LightShape without
  // one here fails, so the recipe of docs/architecture.md ("A local light
  // kind") stays whole. Each lights a point 3 units below it, away from any
  // texel edge and inside a spot's cone.
  const std::map<std::string, std::string> examples{{"point", "point:0.1,3,0.2,5"},
                                                    {"sphere", "sphere:0.1,3,0.2,0.3,5"},
                                                    {"spot", "spot:0.1,3,0.2,0,-1,0,40,5"}};
  const CubeLattice lattice(16);
  ASSERT_EQ(examples.size(), kLightGrammars.size());
  for (size_t k = 0; k < kLightGrammars.size(); ++k) {
    const LightGrammar& g = kLightGrammars[k];
    SCOPED_TRACE(g.kind);
    ASSERT_TRUE(examples.count(g.kind)) << "no example of kind " << g.kind;
    const LocalLight light = parseLocalLight(examples.at(g.kind));
    EXPECT_EQ(light.shape.index(), k) << "kLightGrammars follows LightShape's order";
    EXPECT_STREQ(light.kindName(), g.kind);
    EXPECT_EQ(parseLocalLight(light.canonicalSpec()).canonicalSpec(), light.canonicalSpec());
    const double irradiance = lightIrradiance(light, Vec3::Zero());
    EXPECT_GT(irradiance, 0);
    std::vector<LightTap> shares;
    ASSERT_TRUE(appendDirectionTaps(light, lattice, Vec3::Zero(), shares));
    EXPECT_NEAR(sumOf(shares), 1, 1e-12);
    std::vector<LightTap> taps;
    ASSERT_TRUE(appendLightTaps(light, lattice, Vec3::Zero(), taps));
    EXPECT_NEAR(sumOf(taps), irradiance, 1e-12 * irradiance);
    // Lit as a point of the same power while held: the same irradiance far off.
    const Vec3 far(0.1, -3e3, 0.2);
    if (const std::optional<LocalLight> held = heldAsPoint(light)) {
      EXPECT_NEAR(lightIrradiance(*held, far) * held->emission.x() /
                      (lightIrradiance(light, far) * light.emission.x()),
                  1, 1e-6);
    }
  }
}

TEST(Grammars, TheDocsWriteEveryLightMapAndRotationGrammarAsTheCodeDoes) {
  // Each grammar is written once, in the code (kLightGrammars,
  // kEnvironmentGrammars); the help and docstrings are made from it, and the
  // docs a user reads must say the same.
  for (const char* doc : {"/../docs/lighting.md", "/../README.md"}) {
    std::ifstream in(std::string(ACPCA_DATA_DIR) + doc);
    ASSERT_TRUE(in) << doc;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const LightGrammar& g : kLightGrammars)
      EXPECT_NE(text.find("`" + firstForm(g.grammar) + "`"), std::string::npos)
          << doc << " does not write " << firstForm(g.grammar);
    for (const EnvironmentGrammar& g : kEnvironmentGrammars)
      EXPECT_NE(text.find("`" + firstForm(g.grammar) + "`"), std::string::npos)
          << doc << " does not write " << firstForm(g.grammar);
    for (const char* rotation : {kRotationGrammar, kRotationSweepGrammar})
      EXPECT_NE(text.find(rotation), std::string::npos) << doc << " does not write " << rotation;
  }
  const std::string lines = lightGrammarLines();
  for (const LightGrammar& g : kLightGrammars) EXPECT_NE(lines.find(g.grammar), std::string::npos);
  EXPECT_NE(environmentGrammarList().find("sun:THETA,PHI,SIZE_DEG,INTENSITY"), std::string::npos);
}

}  // namespace
}  // namespace acpca
