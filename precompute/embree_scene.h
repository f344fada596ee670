#pragma once
// Embree scene built from a Scene, and the first-hit G-buffer of a camera.
// Internal to the renderer target: only it links Embree.
#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "precompute/scene.h"
#include "transport/lamp_geometry.h"

namespace acpca {

/// Owns an Embree device and the committed scene: high build quality, and
/// robust (watertight) intersection, since light leaking between triangles
/// through a shared edge shows up in bounced light (tests/physics/
/// interreflection_test.cpp); shadow-ray origins are offset by us.
class EmbreeScene {
 public:
  explicit EmbreeScene(const Scene& scene);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  RTCScene handle() const { return scene_; }
  /// Offset of shadow-ray origins along the normal, relative to the scene size.
  float rayEpsilon() const { return epsilon_; }
  const std::vector<Material>& materials() const { return materials_; }
  /// Zero-area triangles left out of the scene.
  long long degenerateTriangles() const { return degenerateTriangles_; }
  /// The surfaces as traced (kept triangles, spheres), the materials by
  /// geometry id and the shadow rays' start, into a file's lamp geometry.
  void describeSurfaces(LampGeometry& lamps) const;

  /// First hit of a ray; material < 0 when it leaves the scene.
  struct Hit {
    int material = -1;
    Vec3 position;
    Vec3 normal;         ///< geometric, unit, turned to face the ray's origin
    Vec3 shadingNormal;  ///< interpolated (the geometric one when flat), on normal's side
    /// Unit, across shadingNormal, the material's rotation applied
    /// (docs/scenes.md, "Tangents"): what orients an anisotropic lobe.
    Vec3 tangent;
    Eigen::Vector3f albedo;  ///< the material's, times its texture at the hit
  };
  Hit intersect(const Vec3& origin, const Vec3& direction) const;

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  float epsilon_ = 1e-4f;
  long long degenerateTriangles_ = 0;
  std::vector<Material> materials_;        // per geometry ID
  std::vector<float> vertices_, spheres_;  // as describeSurfaces gives them
  std::vector<std::int32_t> triangles_;
  std::vector<const Sphere*> sphereOfGeometry_;  // nullptr for meshes
  /// Per geometry: three shading normals per kept triangle (empty: flat).
  std::vector<std::vector<Eigen::Vector3f>> cornerNormals_;
  /// Per geometry: three tangents per kept triangle (empty: world +X across the normal).
  std::vector<std::vector<Eigen::Vector3f>> cornerTangents_;
  /// Per geometry: its albedo texture (may be null) and, with one, three
  /// texture coordinates per kept triangle.
  std::vector<std::shared_ptr<const Texture>> textures_;
  std::vector<std::vector<Eigen::Vector2f>> cornerUvs_;
};

/// One camera sample of a pixel: where it hit and how it is seen.
struct PixelSample {
  Eigen::Vector3f origin;           ///< hit point pushed off along the geometric normal
  Eigen::Vector3f normal;           ///< shading normal: unit, on the viewer's side
  Eigen::Vector3f geometricNormal;  ///< unit, facing the viewer
  Eigen::Vector3f tangent;          ///< unit, across normal (Hit::tangent)
  Eigen::Vector3f toViewer;         ///< unit
  Eigen::Vector3f albedo;           ///< textured albedo at the hit
  int material = -1;                ///< -1: the sample missed (background)
};

/// Camera samples of every pixel: samples[(y * width + x) * spp + s].
struct GBuffer {
  ImageSize size;
  int samplesPerPixel = 1;
  std::vector<PixelSample> samples;
  /// Per material: whether its lobe turns with the tangent.
  std::vector<bool> anisotropic;
  const PixelSample& at(int x, int y, int s) const {
    return samples[(static_cast<size_t>(y) * size.width + x) * samplesPerPixel + s];
  }
};

/// Lattice texels grouped in 4x4 blocks of one face (16 neighbouring directions:
/// a coherent shadow-ray packet from one point); -1 pads blocks at the edge of a
/// face when R is not a multiple of 4.
std::vector<std::array<int, 16>> texelBlocks(const CubeLattice& lattice);

/// Traces the camera rays of every pixel sample in parallel (TBB).
GBuffer renderGBuffer(const EmbreeScene& scene, const Camera& camera, int samplesPerPixel);

}  // namespace acpca
