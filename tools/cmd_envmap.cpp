// `adaptive-cpca envmap`: what the lattice sees of a lighting, as images.
#include <iostream>

#include "core/error.h"
#include "lighting/envmap_export.h"
#include "lighting/map_source_listing.h"
#include "lighting/map_sources.h"
#include "lighting/rotation.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct EnvmapArgs {
  CommonOptions common;
  std::string env, out, cross, rotate, size = "2048x1024", sun = "auto";
  int cubemap = 32;
  bool withoutSources = false;
  RotationMode rotationMode = RotationMode::Exact;
};

/// The map's compact bright sources (lighting/map_sources.h), and what the
/// lattice gets: the whole map, or with --without-sources the map less them,
/// as a relight's lattice gets it.
struct EnvmapLighting {
  std::vector<MapSource> sources;
  std::unique_ptr<Environment> rest;  ///< null: the whole map
};

EnvmapLighting splitFor(const Environment& env, const std::optional<SourceFinding>& finding,
                        bool withoutSources) {
  if (!finding) return {};
  SplitEnvironment split = env.splitSources(*finding);
  return {std::move(split.sources), withoutSources ? std::move(split.rest) : nullptr};
}

void run(const EnvmapArgs& a) {
  const ImageSize size = parseImageSize(a.size, "--size");
  const EnvRotation rotation = parseSingleRotation(a.rotate, "--rotate");
  const std::optional<SourceFinding> finding = parseSourceFinding(a.sun);
  refuseOutputsOverInputs({a.env}, {a.out, a.cross, a.common.jsonPath});
  const CubeLattice lattice(a.cubemap);
  if (a.withoutSources && !finding)
    throw ParameterError("--without-sources", "",
                         "needs sources to leave out: --sun auto or K, not off");
  const auto env = loadEnvironment(a.env);
  const EnvmapLighting split = splitFor(*env, finding, a.withoutSources);
  const Environment& onLattice = split.rest ? *split.rest : *env;
  const LatticeLighting lighting = computeLighting(onLattice, lattice, rotation, a.rotationMode);
  writeImage(latticeToLatLong(lighting, lattice, size.width, size.height), a.out, ImageFormat::Exr,
             0, true);
  if (!a.cross.empty())
    writeImage(latticeToCross(lighting, lattice, std::max(8 * a.cubemap, 64)), a.cross,
               ImageFormat::Exr, 0, true);
  const Rgb energy = totalEnergy(lighting);
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << (a.cross.empty() ? "" : " and " + a.cross) << ": "
              << env->name() << (split.rest ? " less its sources" : "") << " on 6x" << a.cubemap
              << "x" << a.cubemap << ", energy (sum of radiance x solid angle) "
              << energy.transpose() << "\n";
  const nlohmann::json sources = sourcesJson(turnedSources(split.sources, rotation));
  if (!a.common.quiet && !sources.empty())
    std::cerr << sources.size() << " compact bright source(s) found (listed by --json)\n";
  writeJson(a.common.jsonPath, {{"env", a.env},
                                {"cubemap", a.cubemap},
                                {"without_sources", a.withoutSources},
                                {"sources", sources},
                                {"energy", {energy[0], energy[1], energy[2]}},
                                {"out", a.out},
                                {"cross", a.cross}});
}

}  // namespace

void registerEnvmap(CLI::App& app) {
  auto args = std::make_shared<EnvmapArgs>();
  auto* sub = app.add_subcommand("envmap", "Write what the cube lattice sees of a lighting");
  sub->add_option("env", args->env, "Lighting: an image file, " + environmentGrammarList())
      ->required();
  sub->add_option("--out", args->out, "Lat-long EXR to write")->required();
  sub->add_option("--cross", args->cross, "Also write a horizontal cube cross EXR");
  sub->add_option("--cubemap", args->cubemap, "Cube-map face resolution R");
  sub->add_option("--rotate", args->rotate, std::string(kRotationGrammar) + " in degrees");
  sub->add_option("--size", args->size, "Lat-long size WxH");
  sub->add_option("--sun", args->sun,
                  "A map's compact bright sources (a lat-long map's, sun:'s disc, sky's sun) "
                  "listed by --json: auto, off or K (the brightest K)")
      ->capture_default_str();
  sub->add_flag("--without-sources", args->withoutSources,
                "Write the map less its sources (--sun's), as a relight's lattice gets it; "
                "--json lists what was left out");
  addFastRotationFlag(*sub, args->rotationMode);
  args->common.add(*sub, false);
  nameParameters(
      *sub,
      {{"--cubemap", {"cube-map resolution"}}, {"--rotate", {"rotation"}}, {"--sun", {"sources"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
