// adaptive_cpca.Relighter: a model or transport file relit into numpy
// arrays, as the CLI's relight writes its frames.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/error.h"
#include "core/warning.h"
#include "dataset/batch_relight.h"
#include "dataset/file_info.h"
#include "lighting/domain_lighting.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "lighting/local_light.h"
#include "lighting/map_source_listing.h"
#include "lighting/rotation.h"
#include "lighting/spec_parsing.h"
#include "python/module_parts.h"
#include "python/opening_file.h"
#include "python/to_python.h"
#include "relight/image_composer.h"
#include "relight/local_relight.h"
#include "relight/relight_source.h"

namespace acpca::python {

namespace {

/// A file's lighting domain in words, to tell lightings of one from another's.
std::string domainName(const TransportHeader& h) {
  return h.isLightSet() ? concat(h.lights.size(), " lights")
                        : concat("6x", h.cubemapResolution, "x", h.cubemapResolution);
}

/// Python's max_rank (None, a rank, a fraction or the CLI's text) parsed
/// once, as the CLI parses --max-rank.
RankLimit rankLimitOf(const PyRankLimit& limit) {
  if (!limit) return {};
  if (const int* k = std::get_if<int>(&*limit)) return RankLimit::ofNumber(*k);
  if (const double* f = std::get_if<double>(&*limit)) return RankLimit::ofNumber(*f);
  return RankLimit::parse(std::get<std::string>(*limit));
}

/// A model or transport file opened for relighting.
class Relighter {
 public:
  /// Rows added onto a frame after its relight, in the CLI's order: the
  /// local lights', then the map's sources' (empty: none).
  struct AddedRows {
    const std::vector<float>& local;
    const std::vector<float>& sources;
  };

  explicit Relighter(const std::string& path) : path_(path) {
    openingFile(path, [&] {
      py::gil_scoped_release release;
      source_ = openRelightSource(path);
      return 0;
    });
    py::gil_scoped_release release;
    domain_ = std::make_unique<DomainLighting>(source_.header);
    composer_ = std::make_unique<ImageComposer>(source_.header);
  }

  int width() const { return source_.header.camera.size.width; }
  int height() const { return source_.header.camera.size.height; }
  const std::string& method() const { return source_.method; }
  bool isModel() const { return !source_.dense; }
  py::object info() const { return toPython(describeFile(path_).json); }

  py::array_t<float> coverage() const { return coverageImage(source_.header); }
  py::dict labels(const std::string& aovs) const {
    return labelArrays(source_.header, path_, isModel(), aovs);
  }

  /// Each object's name, by the id the "object" label holds.
  const std::vector<std::string>& objectNames() const { return source_.header.objectNames; }

  py::array_t<float> shading(const py::array_t<float, py::array::c_style>& frame,
                             bool keepNegative) const {
    return frameShadingArray(source_.header, frame, keepNegative);
  }

  /// An environment under a rotation, integrated onto this file's lattice once
  /// (to relight it several times, or to time the relight alone).
  PyLighting lighting(const PyEnvironment& env, double yaw, double pitch, double roll,
                      bool fastRotation, const PySun& sun) const {
    PyLighting l{env.env, EnvRotation{yaw, pitch, roll}, {}, domainName(source_.header), {}};
    validateRotation(l.rotation);
    std::vector<MapSource> sources;
    const Environment& lattice = latticePart(env, sun, sources);
    py::gil_scoped_release release;
    l.values = (*domain_)(lattice, l.rotation,
                          fastRotation ? RotationMode::FastLattice : RotationMode::Exact);
    l.sources = turnedSources(sources, l.rotation);
    return l;
  }

  py::array_t<float> relight(const std::optional<PyEnvironment>& env, double yaw, double pitch,
                             double roll, const PyRankLimit& maxRank, double exposure,
                             const std::string& background, bool fastRotation, OutArgument out,
                             const std::vector<LocalLight>& lights, double anchorSpread,
                             bool keepNegative, const PySun& sun) {
    if (!env && lights.empty())
      throw ParameterError("environment", "None", "give an environment, lights, or both");
    return relightLighting(lighting(env ? *env : PyEnvironment{darkness(), nullptr}, yaw, pitch,
                                    roll, fastRotation, sun),
                           maxRank, exposure, background, std::move(out), lights, anchorSpread,
                           keepNegative);
  }

  py::array_t<float> relightLighting(const PyLighting& lighting, const PyRankLimit& maxRank,
                                     double exposure, const std::string& background,
                                     OutArgument out, const std::vector<LocalLight>& lights,
                                     double anchorSpread, bool keepNegative) {
    requireFinite(exposure, "exposure");
    const Background bg = backgroundOf(background);
    if (lighting.domain != domainName(source_.header))
      throw ParameterError(
          "lighting", lighting.domain,
          concat("was made for another lattice than ", path_, "'s ", domainName(source_.header)));
    OutArray image = outputArray(out, {}, bg);
    {
      py::gil_scoped_release release;
      setRank(maxRank);
      const std::vector<float> local = localRows(lights, anchorSpread);
      const std::vector<float> sources = sourceRows(lighting.sources);
      const AddedRows added{local, sources};
      float* pixels = image.mutable_data();
      if (source_.model) {
        relightModelInto(lighting.values, *lighting.env, lighting.rotation, bg, exposure, added,
                         keepNegative, pixels);
      } else {
        std::vector<double> ms;
        finish(source_.relight({lighting.values}, ms)[0].data(), *lighting.env, lighting.rotation,
               bg, exposure, added, keepNegative, pixels);
      }
    }
    return image;
  }

  /// The light of a lighting's sources, lit exactly, per occupied row in
  /// the file's order (albedo applied, before coverage and exposure): P x 3;
  /// None where it holds none. What adaptive_cpca.torch adds to its relight.
  std::optional<py::array_t<float>> sourceLight(const PyLighting& lighting) const {
    if (lighting.sources.empty()) return std::nullopt;
    std::vector<float> rows;
    {
      py::gil_scoped_release release;
      rows = sourceRows(lighting.sources);
    }
    py::array_t<float> out({static_cast<py::ssize_t>(rows.size() / 3), py::ssize_t{3}});
    std::copy(rows.begin(), rows.end(), out.mutable_data());
    return out;
  }

  /// Every environment under every rotation, environment-major (as the CLI's
  /// batches): N x H x W x C. A transport relights them in one pass over T.
  py::array_t<float> relightBatch(const std::vector<PyEnvironment>& envs,
                                  const std::vector<std::tuple<double, double, double>>& rotations,
                                  const PyRankLimit& maxRank, double exposure,
                                  const std::string& background, bool fastRotation, OutArgument out,
                                  const std::vector<LocalLight>& lights, double anchorSpread,
                                  const std::optional<DoubleArray>& lightPositions,
                                  bool keepNegative, const PySun& sun) {
    requireFinite(exposure, "exposure");
    for (const auto& [yaw, pitch, roll] : rotations) validateRotation({yaw, pitch, roll});
    const Background bg = backgroundOf(background);
    if (envs.empty() || rotations.empty())
      throw ParameterError("batch", "", "give at least one environment and one rotation");
    const std::vector<std::vector<LocalLight>> sets = lightSetsAlong(lights, lightPositions);
    const size_t perSet = envs.size() * rotations.size();
    const py::ssize_t frames = static_cast<py::ssize_t>(perSet * sets.size());
    OutArray images = outputArray(out, {frames}, bg);
    // Each map split once: what its lattice integrates, and its sources.
    std::vector<const Environment*> latticeParts;
    std::vector<std::vector<MapSource>> mapSources(envs.size());
    for (size_t e = 0; e < envs.size(); ++e)
      latticeParts.push_back(&latticePart(envs[e], sun, mapSources[e]));
    {
      py::gil_scoped_release release;
      setRank(maxRank);
      const size_t frameValues = static_cast<size_t>(images.size() / frames);
      const RotationMode mode = fastRotation ? RotationMode::FastLattice : RotationMode::Exact;
      const auto frameOf = [&](size_t i) {
        const auto& [yaw, pitch, roll] = rotations[i % rotations.size()];
        return std::pair{envs[i / rotations.size()].env.get(), EnvRotation{yaw, pitch, roll}};
      };
      const auto lightingOf = [&](size_t i) {
        const auto& [yaw, pitch, roll] = rotations[i % rotations.size()];
        return (*domain_)(*latticeParts[i / rotations.size()], EnvRotation{yaw, pitch, roll}, mode);
      };
      const auto sourcesOf = [&](size_t i) {
        return sourceRows(turnedSources(mapSources[i / rotations.size()], frameOf(i).second));
      };
      for (size_t set = 0; set < sets.size(); ++set) {
        const std::vector<float> local = localRows(sets[set], anchorSpread);
        float* setImages = images.mutable_data() + set * perSet * frameValues;
        relightInGroups(
            perSet, lightingOf, [&](size_t first, const std::vector<LatticeLighting>& lightings) {
              if (source_.model) {  // one projection, then into the array
                source_.model->lightGroup(lightings);
                for (size_t k = 0; k < lightings.size(); ++k) {
                  const auto [env, rotation] = frameOf(first + k);
                  const std::vector<float> sources = sourcesOf(first + k);
                  shadeModelFrameInto(k, *env, rotation, bg, exposure, {local, sources},
                                      keepNegative, setImages + (first + k) * frameValues);
                }
                return;
              }
              std::vector<double> ms;
              const auto rows = source_.relight(lightings, ms);
              for (size_t k = 0; k < rows.size(); ++k) {
                const auto [env, rotation] = frameOf(first + k);
                const std::vector<float> sources = sourcesOf(first + k);
                finish(rows[k].data(), *env, rotation, bg, exposure, {local, sources}, keepNegative,
                       setImages + (first + k) * frameValues);
              }
            });
      }
    }
    return images;
  }

 private:
  /// A background by name; empty: env, or black for a captured light set
  /// (it has no camera to see the environment through), where env is refused.
  Background backgroundOf(const std::string& name) const {
    const bool captured = source_.header.isLightSet();
    const Background bg =
        kBackgroundNames.parse(name.empty() ? (captured ? "black" : "env") : name);
    requireBackgroundShown(source_.header, bg, path_);
    return bg;
  }

  /// The local lights alone, per occupied row (empty without lights).
  std::vector<float> localRows(const std::vector<LocalLight>& lights, double anchorSpread) const {
    if (lights.empty()) return {};
    if (!(anchorSpread >= 0 && anchorSpread <= 64))
      throw ParameterError("anchor spread", anchorSpread, "is not in 0..64 texels");
    return source_.relightLocal(lights, anchorSpread, lamps_);
  }

 public:
  std::string lightMode() const { return kLampModeNames.name(lamps_.mode); }
  void setLightMode(const std::string& mode) { lamps_.mode = kLampModeNames.parse(mode); }
  int lampRays() const { return lamps_.sphereRays; }
  void setLampRays(int rays) { lamps_.sphereRays = parseSphereLampRays(std::to_string(rays)); }

 private:
  void setRank(const PyRankLimit& maxRank) {
    const RankLimit limit = rankLimitOf(maxRank);
    if (!source_.model) {
      if (limit.limited())
        throw ParameterError("maximum rank", limit.text(),
                             concat(path_, " is a transport file, which has no ranks"));
      return;
    }
    source_.model->setMaxRank(-1);
    limit.applyTo(*source_.model);
  }

  /// The caller's array, written in place, or a new one. Anything the
  /// results could not be written into directly is refused: a copy would
  /// leave the caller's array untouched.
  OutArray outputArray(OutArgument& out, std::vector<py::ssize_t> shape, Background bg) const {
    shape.insert(shape.end(), {height(), width(), bg == Background::Alpha ? 4 : 3});
    if (!out) return OutArray(shape);
    std::string wanted;
    for (auto v : shape) wanted += (wanted.empty() ? "" : ", ") + concat(v);
    const std::string expected =
        concat("out must be a writeable C-contiguous float32 array of shape (", wanted, ")");
    if (!out->dtype().is(py::dtype::of<float>()))
      throw py::type_error(
          concat(expected, "; it has dtype ", py::str(out->dtype()).cast<std::string>()));
    const std::vector<py::ssize_t> given(out->shape(), out->shape() + out->ndim());
    if (given != shape) {
      std::string has;
      for (auto v : given) has += (has.empty() ? "" : ", ") + concat(v);
      throw py::value_error(concat(expected, "; it has shape (", has, ")"));
    }
    if (!out->writeable()) throw py::value_error(concat(expected, "; it is read-only"));
    if (!(out->flags() & py::array::c_style))
      throw py::value_error(concat(expected,
                                   "; it is not C-contiguous (a strided view?): "
                                   "pass a contiguous array, or np.ascontiguousarray"));
    return py::reinterpret_borrow<OutArray>(*out);
  }

  /// One frame of a model, relit straight into its image.
  void relightModelInto(const LatticeLighting& lighting, const Environment& env,
                        const EnvRotation& rotation, Background bg, double exposure,
                        const AddedRows& added, bool keepNegative, float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    source_.model->relightInto(lighting, pixels, ImageComposer::channels(bg));
    addRows(added, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  /// Frame k of the group the model's relighter last lit, into its image.
  void shadeModelFrameInto(size_t k, const Environment& env, const EnvRotation& rotation,
                           Background bg, double exposure, const AddedRows& added,
                           bool keepNegative, float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    source_.model->shadeFrameInto(k, pixels, ImageComposer::channels(bg));
    addRows(added, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  /// One frame from per-row values (the dense path) into its image.
  void finish(const float* rowRgb, const Environment& env, const EnvRotation& rotation,
              Background bg, double exposure, const AddedRows& added, bool keepNegative,
              float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    composer_->addRows(rowRgb, pixels, ImageComposer::channels(bg));
    addRows(added, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  void addRows(const AddedRows& added, Background bg, float* pixels) const {
    for (const std::vector<float>* rows : {&added.local, &added.sources})
      if (!rows->empty()) composer_->addRows(rows->data(), pixels, ImageComposer::channels(bg));
  }

  /// What a frame of `env` integrates onto the lattice; its sources, to be lit
  /// exactly, into `sources` (relight --sun; map_suns.cpp).
  const Environment& latticePart(const PyEnvironment& env, const PySun& sun,
                                 std::vector<MapSource>& sources) const {
    const auto warnOnce = [&] {
      if (source_.header.isLightSet()) return;  // its cells hold them, as the CLI's
      std::call_once(*sunWarned_, [&] {
        warn(concat(path_, ": the maps' suns and bright lamps go through the lattice (their ",
                    "shadows come out soft and shifted by up to a texel): ",
                    source_.sourcesUnavailable, "; sun='off' asks for it without this warning"));
      });
    };
    return latticePartOf(env, sun, lamps_.mode == LampMode::Exact, source_.sourcesUnavailable,
                         warnOnce, sources);
  }

  /// The sources' light on every row, lit exactly (empty with none).
  std::vector<float> sourceRows(const std::vector<MapSource>& sources) const {
    if (sources.empty()) return {};
    return source_.relightSources(sources, lamps_.sphereRays);
  }

  /// As the CLI writes images: clamped at zero unless kept, colour scaled by
  /// 2^exposure, alpha kept.
  void finishPixels(double exposure, bool keepNegative, Background bg, float* pixels) const {
    const int channels = bg == Background::Alpha ? 4 : 3;
    const size_t values = static_cast<size_t>(width()) * height() * channels;
    if (!keepNegative) clampNegative(pixels, values, channels);
    if (exposure == 0) return;
    const float scale = static_cast<float>(std::exp2(exposure));
    for (size_t i = 0; i < values; ++i)
      if (channels != 4 || i % 4 != 3) pixels[i] *= scale;
  }

  std::string path_;
  RelightSource source_;
  LampSettings lamps_;
  std::shared_ptr<std::once_flag> sunWarned_ = std::make_shared<std::once_flag>();
  std::unique_ptr<DomainLighting> domain_;  ///< the lattice, or a captured light set's cells
  std::unique_ptr<ImageComposer> composer_;
};

}  // namespace

void registerRelighter(py::module_& m) {
  py::class_<Relighter>(m, "Relighter", "A model (fast path) or transport file (dense path).")
      .def(py::init<const std::string&>(), py::arg("path"))
      .def_property_readonly("width", &Relighter::width)
      .def_property_readonly("height", &Relighter::height)
      .def_property_readonly("method", &Relighter::method)
      .def_property_readonly("is_model", &Relighter::isModel)
      .def_property_readonly("info", &Relighter::info)
      .def_property_readonly("coverage", &Relighter::coverage,
                             "H x W: the share of each pixel's camera samples that hit")
      .def("labels", &Relighter::labels, py::arg("aovs") = "all",
           "The view's per-pixel labels, by name (albedo, normal, depth, position, mask, "
           "object): H x W (x C) arrays, as `relight --aov ... --label-format npy` writes them "
           "(docs/datasets.md).")
      .def_property("light_mode", &Relighter::lightMode, &Relighter::setLightMode,
                    "How lamps are lit: 'exact' (default; shadow rays from each camera sample "
                    "where the file holds its surfaces, else the lattice with a warning) or "
                    "'lattice' (through T's texels), as relight --light-mode")
      .def_property("lamp_rays", &Relighter::lampRays, &Relighter::setLampRays,
                    "Sphere lamps, exact: shadow rays per camera sample where a penumbra may "
                    "fall, a square from 4 to 256 (default 64), as relight --lamp-rays")
      .def_property_readonly("object_names", &Relighter::objectNames,
                             "Each object's name, by the id the object label holds")
      .def("shading", &Relighter::shading, py::arg("frame"), py::kw_only(),
           py::arg("keep_negative") = false,
           "A frame's shading (relit / albedo, H x W x 3) from a frame relit with background "
           "'black' or 'alpha', as the CLI's FRAME_shading files hold it: clamped at zero "
           "unless keep_negative.")
      .def("relight", &Relighter::relight, py::arg("env"), py::kw_only(), py::arg("yaw") = 0.0,
           py::arg("pitch") = 0.0, py::arg("roll") = 0.0, py::arg("max_rank") = py::none(),
           py::arg("exposure") = 0.0, py::arg("background") = "", py::arg("fast_rotation") = false,
           py::arg("out") = py::none(), py::arg("lights") = std::vector<LocalLight>{},
           py::arg("anchor_spread") = kAnchorSpreadTexels, py::arg("keep_negative") = false,
           py::arg("sun") = "auto",
           "One image, H x W x 3 (x 4 with background='alpha'), as `relight` writes it; "
           "lights (Light, PointLight, ...) are added, and light it alone when env is None. "
           "background: 'env' (default; 'black' for a captured light set), 'black' or 'alpha'. "
           "Values below zero (a model's reconstruction can undershoot) are clamped to 0 "
           "unless keep_negative. sun: 'auto' (default), 'off' or K, as relight --sun: the "
           "map's sun and bright lamps split off and lit exactly by shadow rays where the "
           "file holds its surfaces.")
      .def("relight", &Relighter::relightLighting, py::arg("lighting"), py::kw_only(),
           py::arg("max_rank") = py::none(), py::arg("exposure") = 0.0, py::arg("background") = "",
           py::arg("out") = py::none(), py::arg("lights") = std::vector<LocalLight>{},
           py::arg("anchor_spread") = kAnchorSpreadTexels, py::arg("keep_negative") = false,
           "The same from a Lighting made by lighting(): the integration is not repeated.")
      .def("lighting", &Relighter::lighting, py::arg("env"), py::kw_only(), py::arg("yaw") = 0.0,
           py::arg("pitch") = 0.0, py::arg("roll") = 0.0, py::arg("fast_rotation") = false,
           py::arg("sun") = "auto",
           "The environment under a rotation, integrated onto this file's lattice: a Lighting "
           "(without the sources sun= splits off, which it keeps to light exactly).")
      .def("source_light", &Relighter::sourceLight, py::arg("lighting"),
           "The light of lighting's sources (what sun= split off), lit exactly: per occupied "
           "row in the file's order, albedo applied, before coverage and exposure, P x 3 "
           "float32; None where it holds none.")
      .def("relight_batch", &Relighter::relightBatch, py::arg("envs"), py::kw_only(),
           py::arg("rotations") = std::vector<std::tuple<double, double, double>>{{0, 0, 0}},
           py::arg("max_rank") = py::none(), py::arg("exposure") = 0.0, py::arg("background") = "",
           py::arg("fast_rotation") = false, py::arg("out") = py::none(),
           py::arg("lights") = std::vector<LocalLight>{},
           py::arg("anchor_spread") = kAnchorSpreadTexels, py::arg("light_positions") = py::none(),
           py::arg("keep_negative") = false, py::arg("sun") = "auto",
           "Every environment under every (yaw, pitch, roll): N x H x W x C, environment-major; "
           "the lights are added to every frame. light_positions (F x K x 3, K lights): F "
           "times that, the lights moved to row f's positions for the f-th (light-major, as "
           "the CLI's --light-path).");
  m.def(
      "open", [](const std::string& path) { return Relighter(path); }, py::arg("path"),
      "Relighter(path)");
}

}  // namespace acpca::python
