#pragma once
// The objects of the small multi-view scenes the end-to-end suites build: a
// red sphere resting on a grey floor, seen from any side.
namespace acpca::test {

/// A scene file's "objects" member, to follow its "cameras".
inline constexpr const char* kSphereOnFloorObjects = R"("objects": [
  {"shape": "sphere", "center": [0, 0.6, 0], "radius": 0.6,
   "material": {"type": "diffuse", "albedo": [0.7, 0.3, 0.2]}},
  {"shape": "plane", "center": [0, 0, 0], "normal": [0, 1, 0], "size": 4,
   "material": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}}])";

}  // namespace acpca::test
