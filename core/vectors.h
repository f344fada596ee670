#pragma once
// The two small vectors every library speaks in, named once.
#include <Eigen/Core>

namespace acpca {

/// A point or direction in world space (+Y up; docs/lighting.md, "Conventions").
using Vec3 = Eigen::Vector3d;

/// Linear RGB: a radiance, an irradiance, an albedo or an energy, by context.
using Rgb = Eigen::Vector3d;

}  // namespace acpca
