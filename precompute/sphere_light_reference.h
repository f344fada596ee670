#pragma once
// A reference for local lights that no transport goes through: a sphere light
// rendered directly with Embree, each camera sample's shadow rays aimed at
// points of the light's cone and stopped at its surface (so, unlike the
// transport's, an occluder behind the light casts no shadow), times the
// material's BRDF and cosine.
#include <Eigen/Core>
#include <vector>

#include "precompute/scene.h"

namespace acpca {

/// A sphere of uniform radiance.
struct SphereLightSource {
  Vec3 centre = Vec3::Zero();
  double radius = 1;
  Eigen::Vector3d radiance = Eigen::Vector3d::Ones();
};

/// Per occupied pixel (a pixel with any hit sample, in row-major order: the
/// rows of the transport of the same scene and samples), RGB with the albedo:
/// the mean over its hit samples of the light it reflects to the camera,
/// each estimated from lightSamples stratified directions uniform over the
/// light's cone (a relative noise of about 1 / lightSamples for an
/// unshadowed, evenly lit point: the strata leave only the rim's error).
std::vector<float> renderSphereLightReference(const Scene& scene, const SphereLightSource& light,
                                              int samplesPerPixel, int lightSamples);

}  // namespace acpca
