#include "tools/batch_flags.h"

#include "relight/environment.h"
#include "tools/cli_common.h"

namespace acpca::cli {

void BatchFlags::add(CLI::App& sub, BatchRelightOptions& o, const std::string& outHelp) {
  sub.add_option("--env", envs,
                 "Lighting: image (.exr/.hdr lat-long), directory of them, constant:V, "
                 "sun:THETA,PHI,SIZE_DEG,INTENSITY or sky (repeatable)");
  sub.add_option("--light", o.lights,
                 "Local light, added to every frame: point:X,Y,Z,I, sphere:X,Y,Z,RADIUS,L or "
                 "spot:X,Y,Z,DX,DY,DZ,HALF_ANGLE_DEG,I (I and L grey, or R,G,B; repeatable; a "
                 "number may be a sweep A:B:S, a frame per value; docs/lighting.md)");
  sub.add_option("--light-path", o.lightPath,
                 "Local lights that move: a file with one frame's lights per line (specs "
                 "separated by spaces or ';'); every map and rotation is relit under each line");
  sub.add_option("--out", o.out, outHelp)->required();
  sub.add_option("--rotate", rotations, "YAW[,PITCH,ROLL] or a yaw sweep A:B:S (repeatable)");
  sub.add_option("--format", o.format, "exr, png or both (default: from --out, exr in batch)");
  sub.add_option("--exr-compression", exrCompression,
                 "EXR codec: none, rle, zips, zip or piz (default: zips for one image, " +
                     std::string(kExrCompressionNames.name(kBatchExrCompression)) +
                     " for a batch)");
  sub.add_option("--png-level", o.pngLevel, "PNG deflate level, 0 (fastest) to 9")
      ->capture_default_str();
  nameParameters(sub, {{"--env", {"environment"}},
                       {"--rotate", {"rotation"}},
                       {"--format", {"image format"}},
                       {"--exr-compression", {"EXR compression"}},
                       {"--png-level", {"PNG level"}},
                       {"--out", {"output path"}}});
}

void BatchFlags::apply(BatchRelightOptions& o, const std::string& jsonPath) const {
  o.rotations = parseRotationSpecs(rotations);
  o.envs = expandEnvironmentSpecs(envs);
  if (!exrCompression.empty()) o.exrCompression = kExrCompressionNames.parse(exrCompression);
  validateBatchRelight(o);
  std::vector<std::string> inputs = joined(o.envs, {o.input});
  if (!o.lightPath.empty()) inputs.push_back(o.lightPath);
  refuseOutputsOverInputs(inputs, {jsonPath});
}

}  // namespace acpca::cli
