// The analytic environments: constant (the furnace test), a sun disc, and the
// built-in sun-and-sky.
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "lighting/builtin_maps.h"
#include "lighting/environment.h"
#include "lighting/map_sources.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
double toRadians(double degrees) {
  return degrees * kPi / 180.0;
}

Rgb rgbOf(const std::array<double, 3>& v) {
  return {v[0], v[1], v[2]};
}

std::string formatNumber(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

class ConstantEnvironment : public Environment {
 public:
  explicit ConstantEnvironment(const Rgb& radiance) : radiance_(radiance) {}
  std::string name() const override {
    if (radiance_.x() == radiance_.y() && radiance_.y() == radiance_.z())
      return "constant_" + formatNumber(radiance_.x());
    return "constant_" + formatNumber(radiance_.x()) + "_" + formatNumber(radiance_.y()) + "_" +
           formatNumber(radiance_.z());
  }
  Rgb radiance(const Vec3&) const override { return radiance_; }
  void integrate(const CubeLattice& lattice, const Eigen::Matrix3d&,
                 LatticeLighting& lighting) const override {
    for (int j = 0; j < lattice.size(); ++j)  // exact: radiance times solid angle
      for (int c = 0; c < 3; ++c) lighting[3 * j + c] += radiance_[c] * lattice.solidAngle(j);
  }

 private:
  Rgb radiance_;
};

/// A disc of uniform radiance. Its energy, radiance x 2 pi (1 - cos(size/2)), is
/// split over equal-solid-angle samples of the disc, each added to the texel
/// that holds it: the total is exact and the footprint follows the disc.
class SunEnvironment : public Environment {
 public:
  SunEnvironment(double theta, double phi, double size, const Rgb& radiance)
      : theta_(theta), phi_(phi), size_(size), radiance_(radiance) {
    centre_ = directionFromAngles(toRadians(theta), toRadians(phi));
    cosHalf_ = std::cos(0.5 * toRadians(size));
  }
  std::string name() const override {
    return "sun_" + formatNumber(theta_) + "_" + formatNumber(phi_) + "_" + formatNumber(size_) +
           "_" + formatNumber(radiance_.maxCoeff());
  }
  Rgb radiance(const Vec3& d) const override {
    return d.normalized().dot(centre_) >= cosHalf_ ? radiance_ : Rgb::Zero();
  }
  Rgb energy() const { return radiance_ * 2 * kPi * (1 - cosHalf_); }
  /// The disc as a distant source, turned by nothing.
  MapSource source() const {
    MapSource s;
    s.direction = centre_;
    s.radius = 0.5 * toRadians(size_);
    s.radiance = radiance_;
    return s;
  }
  SplitEnvironment splitSources(const SourceFinding& finding) const override {
    SplitEnvironment out;
    if (!discIsSource(0.5 * toRadians(size_), finding)) return out;
    out.sources = {source()};
    setEnergyShares(out.sources, 0);
    out.rest = makeConstantEnvironment(Rgb::Zero());
    return out;
  }
  void integrate(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                 LatticeLighting& lighting) const override {
    // Rings of equal solid angle (cos theta uniform), more of them than the
    // disc spans texels so that its footprint is resolved.
    const double texelAngle = 0.5 * kPi / lattice.resolution();
    const int rings =
        std::clamp(static_cast<int>(std::ceil(kDiscRingsPerTexel * toRadians(size_) / texelAngle)),
                   kMinDiscRings, kMaxDiscRings);
    const int segments = 2 * rings;
    const Vec3 axis = rotation * centre_;
    const Vec3 helper = std::abs(axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
    const Rgb share = energy() / (static_cast<double>(rings) * segments);
    for (int r = 0; r < rings; ++r) {
      const double cosT = 1 - (r + 0.5) / rings * (1 - cosHalf_);
      const double sinT = std::sqrt(std::max(0.0, 1 - cosT * cosT));
      for (int s = 0; s < segments; ++s) {
        const double phi = 2 * kPi * (s + 0.5 * (r & 1)) / segments;
        const Vec3 w = cosT * axis + sinT * (std::cos(phi) * u + std::sin(phi) * v);
        const int j = lattice.texelOf(w);
        for (int c = 0; c < 3; ++c) lighting[3 * j + c] += share[c];
      }
    }
  }

 private:
  double theta_, phi_, size_;
  Rgb radiance_;
  Vec3 centre_;
  double cosHalf_;
};

/// Sun and sky: a blue sky brightening towards the horizon with a glow around
/// the sun, a dim ground below the horizon, and a 2-degree sun 35 degrees from
/// the zenith. On level ground the sun gives about 1.6 and the sky about 1.0 of
/// irradiance, so shadows are crisp but not black and a white diffuse floor
/// shows about 0.8 at exposure 0. Documented in docs/lighting.md.
class SkyEnvironment : public Environment {
 public:
  /// withSun false: the sky alone, what is left once its sun is split off.
  explicit SkyEnvironment(bool withSun = true)
      : sun_(kSkySunTheta, kSkySunPhi, kSkySunSize, rgbOf(kSkySunRadiance)), withSun_(withSun) {
    sunDirection_ = directionFromAngles(toRadians(kSkySunTheta), toRadians(kSkySunPhi));
  }
  std::string name() const override { return "sky"; }
  Rgb radiance(const Vec3& d) const override {
    const Rgb sun = withSun_ ? sun_.radiance(d) : Rgb::Zero();
    return sun.maxCoeff() > 0 ? sun : skyRadiance(d.normalized());
  }
  void integrate(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                 LatticeLighting& lighting) const override {
    integrateSmoothFunction(
        lattice, rotation, [this](const Vec3& d) { return skyRadiance(d); }, kSkySubCells,
        lighting);
    if (withSun_) sun_.integrate(lattice, rotation, lighting);
  }
  SplitEnvironment splitSources(const SourceFinding& finding) const override {
    SplitEnvironment out;
    if (!withSun_ || !discIsSource(0.5 * toRadians(kSkySunSize), finding)) return out;
    out.sources = {sun_.source()};
    out.rest = std::make_unique<SkyEnvironment>(false);
    // The sky's energy, from its integral over a fine lattice.
    const CubeLattice lattice(32);
    LatticeLighting sky(3 * static_cast<size_t>(lattice.size()), 0.0);
    out.rest->integrate(lattice, Eigen::Matrix3d::Identity(), sky);
    double energy = 0;
    for (int j = 0; j < lattice.size(); ++j)
      energy += 0.2126 * sky[3 * j] + 0.7152 * sky[3 * j + 1] + 0.0722 * sky[3 * j + 2];
    setEnergyShares(out.sources, energy);
    return out;
  }

 private:
  Rgb skyRadiance(const Vec3& d) const {
    if (d.y() < 0) return rgbOf(kSkyGround);
    const double t = std::pow(1 - d.y(), kSkyHorizonPower);
    const double glow =
        kSkyGlowStrength * std::exp(-kSkyGlowSharpness * (1 - d.dot(sunDirection_)));
    return (1 - t) * rgbOf(kSkyZenith) + t * rgbOf(kSkyHorizon) + glow * rgbOf(kSkyGlowColour);
  }
  SunEnvironment sun_;
  bool withSun_;
  Vec3 sunDirection_;
};

}  // namespace

std::unique_ptr<Environment> makeConstantEnvironment(const Rgb& radiance) {
  return std::make_unique<ConstantEnvironment>(radiance);
}

std::unique_ptr<Environment> makeSunEnvironment(double theta, double phi, double size,
                                                const Rgb& radiance) {
  return std::make_unique<SunEnvironment>(theta, phi, size, radiance);
}

std::unique_ptr<Environment> makeSkyEnvironment() {
  return std::make_unique<SkyEnvironment>();
}

}  // namespace acpca
