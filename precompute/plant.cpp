// The procedural potted plant ([Mahajan07], Fig. 1): a terracotta pot and a bush of
// curved, tessellated leaves arranged by phyllotaxis on a central stem. Leaves are
// large (tens of pixels at 256x256) so that neighbouring pixels see similar
// shadows: sub-pixel detail would make transport incoherent between pixels.
#include <cmath>
#include <numbers>
#include <random>

#include "precompute/scene.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kLeaves = 280;
constexpr int kLeafShades = 4;
constexpr int kAlongSegments = 14;  // tessellation of a leaf along its length
constexpr int kAcrossSegments = 8;  // and across its width

/// Uniform in [0, 1) from the raw mt19937 output (specified by the standard, so
/// the plant is the same on every platform, unlike std::uniform_*_distribution).
double uniform(std::mt19937& rng) {
  return rng() / 4294967296.0;
}

Eigen::Vector3f f(const Vec3& v) {
  return v.cast<float>();
}

/// A tube of `sides` sides from a to b (stems and leaf stalks).
void addTube(TriangleMesh& mesh, const Vec3& a, const Vec3& b, double radius, int sides) {
  const Vec3 axis = (b - a).normalized();
  const Vec3 helper = std::abs(axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 u = axis.cross(helper).normalized(), v = axis.cross(u);
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i < sides; ++i) {
    const double phi = 2 * kPi * i / sides;
    const Vec3 offset = radius * (std::cos(phi) * u + std::sin(phi) * v);
    mesh.vertices.push_back(f(a + offset));
    mesh.vertices.push_back(f(b + offset));
  }
  for (int i = 0; i < sides; ++i) {
    const int i0 = base + 2 * i, i1 = base + 2 * ((i + 1) % sides);
    mesh.triangles.emplace_back(i0, i1, i0 + 1);
    mesh.triangles.emplace_back(i1, i1 + 1, i0 + 1);
  }
}

/// One leaf: a blade of the given length and width growing from `base` along
/// `axis`, drooping under gravity, its edges curled up about the midrib.
void addLeaf(TriangleMesh& mesh, const Vec3& base, const Vec3& axis, double length, double width,
             double droop, double curl, double twist) {
  Vec3 side = Vec3(0, 1, 0).cross(axis);
  side = side.norm() < 1e-6 ? Vec3(1, 0, 0) : side.normalized();
  Vec3 lift = axis.cross(side).normalized();
  if (lift.y() < 0) lift = -lift;
  const int first = static_cast<int>(mesh.vertices.size());
  for (int i = 0; i <= kAlongSegments; ++i) {
    const double u = 0.02 + 0.98 * i / kAlongSegments;
    // Widest a little below the middle, pointed at the tip.
    const double halfWidth = 0.5 * width * std::pow(std::sin(kPi * std::pow(u, 0.75)), 0.8);
    const Vec3 centre = base + length * u * axis - droop * length * u * u * Vec3(0, 1, 0);
    const double angle = twist * u;  // the blade turns slowly about its midrib
    const Vec3 s = std::cos(angle) * side + std::sin(angle) * lift;
    const Vec3 l = -std::sin(angle) * side + std::cos(angle) * lift;
    for (int k = 0; k <= kAcrossSegments; ++k) {
      const double v = -1 + 2.0 * k / kAcrossSegments;
      mesh.vertices.push_back(f(centre + v * halfWidth * s + curl * v * v * halfWidth * l));
    }
  }
  const int stride = kAcrossSegments + 1;
  for (int i = 0; i < kAlongSegments; ++i)
    for (int k = 0; k < kAcrossSegments; ++k) {
      const int a = first + i * stride + k, b = a + stride;
      mesh.triangles.emplace_back(a, b, a + 1);
      // The tip row has zero width: its points coincide, and a second triangle
      // there would have no area.
      if (i + 1 < kAlongSegments) mesh.triangles.emplace_back(a + 1, b, b + 1);
    }
}

/// The pot: a tapered, open-topped wall with a rim, filled with soil.
void addPot(Scene& scene) {
  const Material terracotta{Material::Type::Diffuse, {0.62f, 0.32f, 0.2f}};
  const Material soil{Material::Type::Diffuse, {0.14f, 0.1f, 0.07f}};
  TriangleMesh pot = emptyMesh("pot", terracotta);
  const int segments = 64;
  const double profile[][2] = {{0.30, 0.0},  {0.40, 0.50}, {0.44, 0.50}, {0.44, 0.60},
                               {0.40, 0.60}, {0.38, 0.50}};  // (radius, height) around the rim
  const int rings = static_cast<int>(std::size(profile));
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const double phi = 2 * kPi * k / segments;
      pot.vertices.emplace_back(float(profile[r][0] * std::cos(phi)), float(profile[r][1]),
                                float(profile[r][0] * std::sin(phi)));
    }
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      const int a = r * segments + k, b = r * segments + (k + 1) % segments;
      pot.triangles.emplace_back(a, b, a + segments);
      pot.triangles.emplace_back(b, b + segments, a + segments);
    }
  scene.meshes.push_back(std::move(pot));
  TriangleMesh earth = emptyMesh("soil", soil);
  earth.vertices.emplace_back(0.f, 0.52f, 0.f);
  for (int k = 0; k < segments; ++k) {
    const double phi = 2 * kPi * k / segments;
    earth.vertices.emplace_back(float(0.385 * std::cos(phi)), 0.5f, float(0.385 * std::sin(phi)));
  }
  for (int k = 0; k < segments; ++k) earth.triangles.emplace_back(0, 1 + k, 1 + (k + 1) % segments);
  scene.meshes.push_back(std::move(earth));
}

}  // namespace

Scene makePlantScene() {
  Scene scene;
  scene.name = "plant";
  scene.camera.eye = {0, 2.3, 4.6};
  scene.camera.target = {0, 0.95, 0};
  scene.camera.fovDegrees = 38;
  scene.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 14,
                                  {Material::Type::Diffuse, {0.55f, 0.55f, 0.52f}}, "ground"));
  addPot(scene);

  const Material stemMaterial{Material::Type::Diffuse, {0.25f, 0.35f, 0.12f}};
  TriangleMesh stems = emptyMesh("stems", stemMaterial);
  const double stemTop = 2.0, stemBottom = 0.5;
  addTube(stems, {0, stemBottom, 0}, {0, stemTop, 0}, 0.025, 8);

  std::vector<TriangleMesh> leaves;
  for (int shade = 0; shade < kLeafShades; ++shade) {
    const float t = shade / float(kLeafShades - 1);
    leaves.push_back(emptyMesh(
        "leaves",
        {Material::Type::Diffuse, {0.10f + 0.06f * t, 0.32f + 0.16f * t, 0.07f + 0.03f * t}}));
  }
  std::mt19937 rng(20070805u);
  const double goldenAngle = kPi * (3 - std::sqrt(5.0));
  for (int k = 0; k < kLeaves; ++k) {
    const double t = (k + 0.5) / kLeaves;  // 0 at the bottom of the stem, 1 at the top
    const double height = 0.62 + (stemTop - 0.7) * std::pow(t, 0.85);
    const double azimuth = k * goldenAngle + 0.2 * (uniform(rng) - 0.5);
    // Lower leaves reach out nearly level and droop; upper ones point upwards.
    const double elevation = (-0.05 + 0.9 * t + 0.25 * (uniform(rng) - 0.5)) * 0.5 * kPi * 0.8;
    const Vec3 out(std::sin(azimuth), 0, std::cos(azimuth));
    const Vec3 axis =
        (std::cos(elevation) * out + std::sin(elevation) * Vec3(0, 1, 0)).normalized();
    const double stalk = 0.06 + 0.12 * (1 - t) * uniform(rng);
    const Vec3 stemPoint(0, height, 0);
    const Vec3 leafBase = stemPoint + stalk * (out + 0.6 * Vec3(0, 1, 0)).normalized();
    addTube(stems, stemPoint, leafBase, 0.008, 5);
    const double size = (1.0 - 0.45 * t) * (0.85 + 0.3 * uniform(rng));
    addLeaf(leaves[k % kLeafShades], leafBase, axis, 0.72 * size, 0.26 * size,
            0.25 + 0.3 * uniform(rng), 0.35, 0.6 * (uniform(rng) - 0.5));
  }
  scene.meshes.push_back(std::move(stems));
  for (auto& m : leaves) scene.meshes.push_back(std::move(m));
  return scene;
}

}  // namespace acpca
