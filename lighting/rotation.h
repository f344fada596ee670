#pragma once
// Environment rotation of docs/design.md section 3: R = Rz(roll) Rx(pitch) Ry(yaw),
// degrees, right-handed, about fixed world axes; a feature the map holds at d0
// lights the scene from R d0, i.e. L_rotated(d) = L(R^T d).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace acpca {

struct EnvRotation {
  double yaw = 0, pitch = 0, roll = 0;  ///< degrees
  bool isIdentity() const { return yaw == 0 && pitch == 0 && roll == 0; }
  /// "y30" or "y30_p10_r5", as output file names use it.
  std::string label() const;
};

Eigen::Matrix3d rotationMatrix(const EnvRotation& r);

/// Throws ParameterError ("yaw", "pitch" or "roll") for an angle that is not a
/// finite number, as the text specs are refused.
void validateRotation(const EnvRotation& r);

/// The --rotate grammar, written once: the parser's errors quote it, the
/// CLI's help is made from it, and a test holds README.md and
/// docs/lighting.md to it. Degrees; a sweep turns the yaw alone.
inline constexpr const char* kRotationGrammar = "YAW[,PITCH,ROLL]";
inline constexpr const char* kRotationSweepGrammar = "A:B:S";

/// Parses one --rotate SPEC: kRotationGrammar or kRotationSweepGrammar (yaw
/// from A inclusive to B exclusive in steps of S). Throws UserError naming the spec.
std::vector<EnvRotation> parseRotationSpec(const std::string& spec);
/// One rotation, "YAW[,PITCH,ROLL]" (empty: the identity); a sweep is refused,
/// the UserError naming `flag`.
EnvRotation parseSingleRotation(const std::string& spec, const std::string& flag);
/// Every spec's rotations in order; no spec: the identity alone.
std::vector<EnvRotation> parseRotationSpecs(const std::vector<std::string>& specs);

}  // namespace acpca
