#include "precompute/embree_scene.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include "core/error.h"
#include "occlusion/embree_device.h"

namespace acpca {

namespace {

void checkDevice(RTCDevice device, const char* what) {
  const RTCError code = rtcGetDeviceError(device);
  ACPCA_CHECK(code == RTC_ERROR_NONE, "Embree failed while ", what, " (error ",
              static_cast<int>(code), ")");
}

}  // namespace

EmbreeScene::EmbreeScene(const Scene& scene) {
  scene.validate();
  device_ = newEmbreeDevice();
  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
  epsilon_ = static_cast<float>(1e-5 * scene.extent());

  for (const auto& mesh : scene.meshes) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertices.size()));
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      for (int c = 0; c < 3; ++c) v[3 * i + c] = mesh.vertices[i][c];
    // Zero-area triangles (repeated or collinear corners) have no normal and
    // cover nothing: they are left out rather than risk a NaN normal on a hit.
    std::vector<Eigen::Vector3i> kept;
    std::vector<Eigen::Vector3f> keptNormals;   // three per kept triangle
    std::vector<Eigen::Vector3f> keptTangents;  // three per kept triangle
    std::vector<Eigen::Vector2f> keptUvs;       // three per kept triangle, with a texture
    kept.reserve(mesh.triangles.size());
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& tri = mesh.triangles[i];
      const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>(),
                            b = mesh.vertices[tri[1]].cast<double>(),
                            c = mesh.vertices[tri[2]].cast<double>();
      const double twiceArea = (b - a).cross(c - a).norm();
      const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
      if (twiceArea > 1e-12 * longest * longest) {
        kept.push_back(tri);
        if (!mesh.normals.empty())
          keptNormals.insert(keptNormals.end(), mesh.normals.begin() + 3 * i,
                             mesh.normals.begin() + 3 * i + 3);
        if (!mesh.tangents.empty())
          keptTangents.insert(keptTangents.end(), mesh.tangents.begin() + 3 * i,
                              mesh.tangents.begin() + 3 * i + 3);
        if (mesh.albedoTexture)
          keptUvs.insert(keptUvs.end(), mesh.uvs.begin() + 3 * i, mesh.uvs.begin() + 3 * i + 3);
      } else {
        ++degenerateTriangles_;
      }
    }
    auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), kept.size()));
    const auto firstVertex = static_cast<std::int32_t>(vertices_.size() / 3);
    vertices_.insert(vertices_.end(), v, v + 3 * mesh.vertices.size());
    for (size_t i = 0; i < kept.size(); ++i)
      for (int c = 0; c < 3; ++c) {
        t[3 * i + c] = static_cast<unsigned>(kept[i][c]);
        triangles_.push_back(firstVertex + kept[i][c]);
      }
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    ACPCA_CHECK(id == materials_.size(), "geometry id ", id);
    materials_.push_back(mesh.material);
    sphereOfGeometry_.push_back(nullptr);
    cornerNormals_.push_back(std::move(keptNormals));
    cornerTangents_.push_back(std::move(keptTangents));
    textures_.push_back(mesh.albedoTexture);
    cornerUvs_.push_back(std::move(keptUvs));
  }
  for (const auto& sphere : scene.spheres) {
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    v[0] = float(sphere.center.x()), v[1] = float(sphere.center.y());
    v[2] = float(sphere.center.z()), v[3] = float(sphere.radius);
    spheres_.insert(spheres_.end(), v, v + 4);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    ACPCA_CHECK(id == materials_.size(), "geometry id ", id);
    materials_.push_back(sphere.material);
    sphereOfGeometry_.push_back(&sphere);
    cornerNormals_.emplace_back();
    cornerTangents_.emplace_back();
    textures_.emplace_back();
    cornerUvs_.emplace_back();
  }
  rtcCommitScene(scene_);
  checkDevice(device_, "building the scene");
}

void EmbreeScene::describeSurfaces(LampGeometry& lamps) const {
  lamps.vertices = vertices_;
  lamps.triangles = triangles_;
  lamps.spheres = spheres_;
  lamps.materials = materials_;
  lamps.rayEpsilon = epsilon_;
}

EmbreeScene::~EmbreeScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

EmbreeScene::Hit EmbreeScene::intersect(const Vec3& origin, const Vec3& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = float(origin.x()), rh.ray.org_y = float(origin.y()),
  rh.ray.org_z = float(origin.z());
  rh.ray.dir_x = float(direction.x()), rh.ray.dir_y = float(direction.y());
  rh.ray.dir_z = float(direction.z());
  rh.ray.tnear = 0;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  Hit hit;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.material = static_cast<int>(rh.hit.geomID);
  hit.position = origin + double(rh.ray.tfar) * direction;
  hit.albedo = materials_[rh.hit.geomID].albedo;
  if (const Texture* texture = textures_[rh.hit.geomID].get()) {
    // Embree's barycentrics: p = (1 - u - v) p0 + u p1 + v p2.
    const float u = rh.hit.u, v = rh.hit.v;
    const Eigen::Vector2f* uv = &cornerUvs_[rh.hit.geomID][3 * size_t(rh.hit.primID)];
    hit.albedo =
        hit.albedo.cwiseProduct(texture->sample((1 - u - v) * uv[0] + u * uv[1] + v * uv[2]));
  }
  const Sphere* sphere = sphereOfGeometry_[rh.hit.geomID];
  Vec3 tangentHint = Vec3::UnitX();
  if (sphere) {
    // Exact normal, and the hit point snapped back onto the true sphere.
    hit.normal = (hit.position - sphere->center).normalized();
    hit.position = sphere->center + sphere->radius * hit.normal;
    hit.shadingNormal = hit.normal;
    tangentHint = Vec3::UnitY().cross(hit.normal);  // along the parallels about +Y
  } else {
    hit.normal = Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z).normalized();
    hit.shadingNormal = hit.normal;
    // Embree's barycentrics: p = (1 - u - v) p0 + u p1 + v p2.
    const double u = rh.hit.u, v = rh.hit.v;
    const size_t first = 3 * static_cast<size_t>(rh.hit.primID);
    const auto interpolate = [&](const std::vector<Eigen::Vector3f>& corners) -> Vec3 {
      return (1 - u - v) * corners[first].cast<double>() + u * corners[first + 1].cast<double>() +
             v * corners[first + 2].cast<double>();
    };
    if (const auto& corners = cornerNormals_[rh.hit.geomID]; !corners.empty()) {
      const Vec3 n = interpolate(corners);
      if (n.norm() > 1e-12) hit.shadingNormal = n.normalized();
    }
    if (const auto& corners = cornerTangents_[rh.hit.geomID]; !corners.empty())
      tangentHint = interpolate(corners);
  }
  if (hit.normal.dot(direction) > 0) hit.normal = -hit.normal;  // two-sided: face the viewer
  // The shading normal lies on the side of the surface the viewer sees.
  if (hit.shadingNormal.dot(hit.normal) < 0) hit.shadingNormal = -hit.shadingNormal;
  hit.tangent = turnedTangent(hit.shadingNormal, tangentAcross(hit.shadingNormal, tangentHint),
                              materials_[rh.hit.geomID].rotationDegrees);
  return hit;
}

std::vector<std::array<int, 16>> texelBlocks(const CubeLattice& lattice) {
  const int r = lattice.resolution();
  std::vector<std::array<int, 16>> blocks;
  for (int face = 0; face < CubeLattice::kFaces; ++face)
    for (int row0 = 0; row0 < r; row0 += 4)
      for (int col0 = 0; col0 < r; col0 += 4) {
        std::array<int, 16> block;
        for (int i = 0; i < 16; ++i) {
          const int row = row0 + i / 4, col = col0 + i % 4;
          block[i] = row < r && col < r ? lattice.texelIndex({face, row, col}) : -1;
        }
        blocks.push_back(block);
      }
  return blocks;
}

GBuffer renderGBuffer(const EmbreeScene& scene, const Camera& camera, int samplesPerPixel) {
  GBuffer g;
  g.size = camera.size;
  g.samplesPerPixel = samplesPerPixel;
  for (const Material& m : scene.materials()) g.anisotropic.push_back(m.anisotropic());
  g.samples.resize(static_cast<size_t>(camera.size.pixels()) * samplesPerPixel);
  const float epsilon = scene.rayEpsilon();
  tbb::parallel_for(tbb::blocked_range<int>(0, camera.size.height), [&](const auto& rows) {
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = 0; x < camera.size.width; ++x)
        for (int s = 0; s < samplesPerPixel; ++s) {
          const Eigen::Vector2d o = pixelSampleOffset(s);
          const Vec3 dir = camera.rayDirection(x + o.x(), y + o.y());
          const auto hit = scene.intersect(camera.eye, dir);
          PixelSample& ps =
              g.samples[(static_cast<size_t>(y) * camera.size.width + x) * samplesPerPixel + s];
          ps.material = hit.material;
          if (hit.material < 0) continue;
          ps.normal = hit.shadingNormal.cast<float>();
          ps.geometricNormal = hit.normal.cast<float>();
          ps.tangent = hit.tangent.cast<float>();
          ps.toViewer = (-dir).cast<float>();
          ps.albedo = hit.albedo;
          // Pushed off along the geometric normal so shadow rays miss their own
          // surface whatever the shading normal says.
          ps.origin = (hit.position + epsilon * hit.normal).cast<float>();
        }
  });
  return g;
}

}  // namespace acpca
