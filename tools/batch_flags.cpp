#include "tools/batch_flags.h"

#include "lighting/environment.h"
#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "lighting/rotation.h"
#include "relight/lamp_light.h"
#include "tools/cli_common.h"

namespace acpca::cli {

void BatchFlags::add(CLI::App& sub, BatchRelightOptions& o, const std::string& outHelp) {
  sub.add_option("--env", envs,
                 "Lighting: image (.exr/.hdr lat-long, 4:3 cube cross), directory of them, " +
                     environmentGrammarList() + " (repeatable)");
  sub.add_option("--light", o.lights,
                 "Local light, added to every frame (repeatable; a number may be a sweep A:B:S, "
                 "a frame per value; docs/lighting.md):\n" +
                     lightGrammarLines());
  sub.add_option("--light-path", o.lightPath,
                 "Local lights that move: a file with one frame's lights per line (specs "
                 "separated by spaces or ';'); every map and rotation is relit under each line");
  sub.add_option("--out", o.out, outHelp)->required();
  sub.add_option("--rotate", rotations,
                 concat(kRotationGrammar, " in degrees or a yaw sweep ", kRotationSweepGrammar,
                        " (repeatable)"));
  sub.add_option("--format", o.format,
                 concat(kImageFormatNames.list(),
                        " (png: 8-bit, png16: 16-bit), a comma-separated list of them, or both "
                        "(exr,png); default: from --out, exr in a batch. EXR and PNG frames carry "
                        "their colour space, camera and lighting in their header; npy holds "
                        "none (a batch's manifest.jsonl lists it)"));
  sub.add_option("--tone", tone,
                 "PNG tone curve: clamp (default) or aces (Narkowicz's ACES filmic fit)");
  sub.add_option("--exr-compression", exrCompression,
                 "EXR codec: none, rle, zips, zip or piz (default: zips for one image, " +
                     std::string(kExrCompressionNames.name(kBatchExrCompression)) +
                     " for a batch)");
  sub.add_option("--png-level", o.pngLevel, "PNG deflate level, 0 (fastest) to 9")
      ->capture_default_str();
  envSample =
      sub.add_option("--env-sample", o.sampling.count,
                     "Draw K lightings (map, rotation, exposure) from the --env maps instead of "
                     "every map x rotation: frames sample_NNNNN, the same for the same --seed");
  sub.add_option("--seed", o.sampling.seed, "Seed of the lighting draws (--env-sample)")
      ->capture_default_str();
  sub.add_option("--sample-rotation", sampleRotation,
                 "Drawn rotations: yaw (level horizon, default) or sphere (uniform over all "
                 "rotations)");
  sub.add_option("--exposure-jitter", o.sampling.exposureJitter,
                 "Drawn exposure offsets: uniform in +-STOPS (--env-sample)");
  sub.add_option("--aov", aovs,
                 "Per-pixel labels: " + kAovNames.list() +
                     " (comma-separated), or the presets all, intrinsic, geometry; the view's "
                     "are written once (labels.exr), shading per frame (docs/datasets.md)");
  sub.add_flag("--lighting-exr", o.lightingImages,
               "Write each frame's lattice lighting beside it, FRAME_lighting.exr (lat-long, "
               "8R x 4R, before exposure)");
  shardSize = sub.add_option("--shard-size", o.shardSize,
                             "Pack the frames N to a tar (NAME-000000.tar, ..., NAME-shards.json; "
                             "WebDataset style: each frame's files under its index)");
  sub.add_flag("--colmap", o.colmap,
               "Write COLMAP's text model (sparse/0: cameras.txt, images.txt, points3D.txt) "
               "beside transforms.json");
  sub.add_option("--label-format", labelFormat, "Labels as exr (float), npy or both (default exr)");
  sub.add_flag("--keep-negative", o.keepNegative,
               "Write the raw reconstruction: frames and shading keep values below zero "
               "(default: clamped to 0; relight --json counts them per frame)");
  sub.add_option("--lamp-rays", lampRays,
                 concat("Sphere lamps and a map's sources, exact: shadow rays per camera sample "
                        "where a penumbra may fall, a square from 4 to ",
                        kMaxSphereLampRays, " (default ", kDefaultSphereLampRays,
                        "; fewer: faster, noisier penumbrae)"));
  sub.add_option("--sun", sun,
                 "A map's sun and bright lamps: auto (default: found, split off and lit "
                 "exactly as distant discs by shadow rays where the file holds its surfaces), "
                 "K (at most K of them) or off (the whole map through the lattice, as before)")
      ->capture_default_str();
  nameParameters(sub, {{"--env", {"environment"}},
                       {"--lamp-rays", {"lamp rays"}},
                       {"--sun", {"sources"}},
                       {"--rotate", {"rotation"}},
                       {"--format", {"image format"}},
                       {"--exr-compression", {"EXR compression"}},
                       {"--png-level", {"PNG level"}},
                       {"--aov", {"AOV"}},
                       {"--colmap", {"COLMAP"}},
                       {"--shard-size", {"shard size"}},
                       {"--tone", {"tone curve"}},
                       {"--env-sample", {"environment samples"}},
                       {"--sample-rotation", {"sampled rotation"}},
                       {"--exposure-jitter", {"exposure jitter"}},
                       {"--label-format", {"label format"}},
                       {"--out", {"output path"}}});
}

BatchPlan BatchFlags::apply(BatchRelightOptions& o, const std::string& jsonPath) const {
  if (!lampRays.empty()) o.lamps.sphereRays = parseSphereLampRays(lampRays);
  o.sources = parseSourceFinding(sun);
  o.rotations = parseRotationSpecs(rotations);
  o.envs = expandEnvironmentSpecs(envs);
  if (!exrCompression.empty()) o.exrCompression = kExrCompressionNames.parse(exrCompression);
  o.aovs = parseAovList(aovs);
  if (!tone.empty()) o.tone = kToneCurveNames.parse(tone);
  if (!sampleRotation.empty()) o.sampling.rotation = kSampledRotationNames.parse(sampleRotation);
  if (envSample->count() > 0) validateLightingSampling(o.sampling);
  if (shardSize->count() > 0 && o.shardSize < 1)
    throw ParameterError("shard size", o.shardSize, "must be at least 1");
  if (!labelFormat.empty()) o.labelFormat = kLabelFormatNames.parse(labelFormat);
  BatchPlan plan = planBatchRelight(o);
  std::vector<std::string> inputs = joined(o.envs, o.viewInputs());
  if (!o.lightPath.empty()) inputs.push_back(o.lightPath);
  refuseOutputsOverInputs(inputs, {jsonPath});
  return plan;
}

}  // namespace acpca::cli
