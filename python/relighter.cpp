// adaptive_cpca.Relighter: a model or transport file relit into numpy
// arrays, as the CLI's relight writes its frames.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "core/error.h"
#include "core/version.h"
#include "core/warning.h"
#include "dataset/batch_relight.h"
#include "dataset/file_info.h"
#include "dataset/pixel_labels.h"
#include "imageio/image_file.h"
#include "imageio/image_output.h"
#include "lighting/domain_lighting.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "lighting/lighting_sampler.h"
#include "lighting/local_light.h"
#include "lighting/rotation.h"
#include "lighting/spec_parsing.h"
#include "python/long_calls.h"
#include "python/opening_file.h"
#include "python/to_python.h"
#include "relight/image_composer.h"
#include "relight/local_relight.h"
#include "relight/relight_source.h"

#include "python/module_parts.h"

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

  /// Coverage of every pixel, H x W (0 for background).
  py::array_t<float> coverage() const {
    py::array_t<float> out({height(), width()});
    float* p = out.mutable_data();
    std::fill(p, p + out.size(), 0.0f);
    for (long long r = 0; r < source_.header.rows(); ++r)
      p[source_.header.pixels[r]] = source_.header.coverage[r];
    return out;
  }

  /// The view's per-pixel labels by AOV name: H x W (x C) float32, object
  /// int32; the very values `relight --aov ... --label-format npy` writes.
  py::dict labels(const std::string& aovs) const {
    const std::vector<Aov> chosen = parseAovList(aovs);
    requireAovs(source_.header, chosen, path_, isModel());
    py::dict out;
    for (const LabelLayer& layer : viewLabels(source_.header, chosen)) {
      std::vector<py::ssize_t> shape{height(), width()};
      if (layer.channels.size() > 1)
        shape.push_back(static_cast<py::ssize_t>(layer.channels.size()));
      if (layer.aov == Aov::Object) {
        py::array_t<std::int32_t> ids(shape);
        std::copy(layer.values.begin(), layer.values.end(), ids.mutable_data());
        out[kAovNames.name(layer.aov)] = ids;
      } else {
        py::array_t<float> values(shape);
        std::copy(layer.values.begin(), layer.values.end(), values.mutable_data());
        out[kAovNames.name(layer.aov)] = values;
      }
    }
    return out;
  }

  /// Each object's name, by the id the "object" label holds.
  const std::vector<std::string>& objectNames() const { return source_.header.objectNames; }

  /// The shading of a frame relit over a black or transparent background:
  /// frame / albedo label, 0 where the albedo is 0 (H x W x 3), as the CLI's
  /// FRAME_shading files hold it.
  py::array_t<float> shading(const py::array_t<float, py::array::c_style>& frame,
                             bool keepNegative) const {
    const py::ssize_t channels = frame.ndim() == 3 ? frame.shape(2) : 0;
    if (frame.ndim() != 3 || frame.shape(0) != height() || frame.shape(1) != width() ||
        (channels != 3 && channels != 4))
      throw ParameterError("frame", concat(frame.ndim(), " dimensions"),
                           concat("is not ", height(), " x ", width(), " x 3 or 4"));
    py::array_t<float> out(std::vector<py::ssize_t>{height(), width(), 3});
    const std::vector<float> background(static_cast<size_t>(frame.size()), 0.0f);
    frameShading(source_.header, frame.data(), background.data(), static_cast<int>(channels),
                 out.mutable_data(), keepNegative);
    return out;
  }

  /// An environment under a rotation, integrated onto this file's lattice once
  /// (to relight it several times, or to time the relight alone).
  PyLighting lighting(const PyEnvironment& env, double yaw, double pitch, double roll,
                      bool fastRotation) const {
    PyLighting l{env.env, EnvRotation{yaw, pitch, roll}, {}, domainName(source_.header)};
    validateRotation(l.rotation);
    py::gil_scoped_release release;
    l.values = (*domain_)(*env.env, l.rotation,
                          fastRotation ? RotationMode::FastLattice : RotationMode::Exact);
    return l;
  }

  py::array_t<float> relight(const std::optional<PyEnvironment>& env, double yaw, double pitch,
                             double roll, const PyRankLimit& maxRank, double exposure,
                             const std::string& background, bool fastRotation, OutArgument out,
                             const std::vector<LocalLight>& lights, double anchorSpread,
                             bool keepNegative) {
    if (!env && lights.empty())
      throw ParameterError("environment", "None", "give an environment, lights, or both");
    return relightLighting(
        lighting(env ? *env : PyEnvironment{darkness()}, yaw, pitch, roll, fastRotation), maxRank,
        exposure, background, std::move(out), lights, anchorSpread, keepNegative);
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
      float* pixels = image.mutable_data();
      if (source_.model) {
        relightModelInto(lighting.values, *lighting.env, lighting.rotation, bg, exposure, local,
                         keepNegative, pixels);
      } else {
        std::vector<double> ms;
        finish(source_.relight({lighting.values}, ms)[0].data(), *lighting.env, lighting.rotation,
               bg, exposure, local, keepNegative, pixels);
      }
    }
    return image;
  }

  /// Every environment under every rotation, environment-major (as the CLI's
  /// batches): N x H x W x C. A transport relights them in one pass over T.
  py::array_t<float> relightBatch(const std::vector<PyEnvironment>& envs,
                                  const std::vector<std::tuple<double, double, double>>& rotations,
                                  const PyRankLimit& maxRank, double exposure,
                                  const std::string& background, bool fastRotation, OutArgument out,
                                  const std::vector<LocalLight>& lights, double anchorSpread,
                                  const std::optional<DoubleArray>& lightPositions,
                                  bool keepNegative) {
    requireFinite(exposure, "exposure");
    for (const auto& [yaw, pitch, roll] : rotations) validateRotation({yaw, pitch, roll});
    const Background bg = backgroundOf(background);
    if (envs.empty() || rotations.empty())
      throw ParameterError("batch", "", "give at least one environment and one rotation");
    const std::vector<std::vector<LocalLight>> sets = lightSets(lights, lightPositions);
    const size_t perSet = envs.size() * rotations.size();
    const py::ssize_t frames = static_cast<py::ssize_t>(perSet * sets.size());
    OutArray images = outputArray(out, {frames}, bg);
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
        const auto [env, rotation] = frameOf(i);
        return (*domain_)(*env, rotation, mode);
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
                  shadeModelFrameInto(k, *env, rotation, bg, exposure, local, keepNegative,
                                      setImages + (first + k) * frameValues);
                }
                return;
              }
              std::vector<double> ms;
              const auto rows = source_.relight(lightings, ms);
              for (size_t k = 0; k < rows.size(); ++k) {
                const auto [env, rotation] = frameOf(first + k);
                finish(rows[k].data(), *env, rotation, bg, exposure, local, keepNegative,
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

  /// The batch's light sets: the lights as given, or, with positions (F x K
  /// x 3 for K lights), F sets of those lights moved to each row's positions.
  static std::vector<std::vector<LocalLight>> lightSets(
      const std::vector<LocalLight>& lights, const std::optional<DoubleArray>& positions) {
    if (!positions) return {lights};
    const DoubleArray& p = *positions;
    if (p.ndim() != 3 || p.shape(1) != static_cast<py::ssize_t>(lights.size()) || p.shape(2) != 3)
      throw py::value_error(concat("light_positions must be F x ", lights.size(),
                                   " x 3: a position for each of the lights in each frame"));
    std::vector<std::vector<LocalLight>> sets;
    for (py::ssize_t f = 0; f < p.shape(0); ++f) {
      std::vector<LocalLight> set = lights;
      for (size_t k = 0; k < set.size(); ++k) {
        set[k].position = Vec3(p.at(f, k, 0), p.at(f, k, 1), p.at(f, k, 2));
        set[k].spec.clear();
        set[k] = madeLight(set[k]);
      }
      sets.push_back(std::move(set));
    }
    if (sets.empty()) throw py::value_error("light_positions holds no frames");
    return sets;
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
                        const std::vector<float>& local, bool keepNegative, float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    source_.model->relightInto(lighting, pixels, ImageComposer::channels(bg));
    addLocal(local, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  /// Frame k of the group the model's relighter last lit, into its image.
  void shadeModelFrameInto(size_t k, const Environment& env, const EnvRotation& rotation,
                           Background bg, double exposure, const std::vector<float>& local,
                           bool keepNegative, float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    source_.model->shadeFrameInto(k, pixels, ImageComposer::channels(bg));
    addLocal(local, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  /// One frame from per-row values (the dense path) into its image.
  void finish(const float* rowRgb, const Environment& env, const EnvRotation& rotation,
              Background bg, double exposure, const std::vector<float>& local, bool keepNegative,
              float* pixels) const {
    composer_->background(bg, env, rotationMatrix(rotation), pixels);
    composer_->addRows(rowRgb, pixels, ImageComposer::channels(bg));
    addLocal(local, bg, pixels);
    finishPixels(exposure, keepNegative, bg, pixels);
  }

  void addLocal(const std::vector<float>& local, Background bg, float* pixels) const {
    if (!local.empty()) composer_->addRows(local.data(), pixels, ImageComposer::channels(bg));
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
           "One image, H x W x 3 (x 4 with background='alpha'), as `relight` writes it; "
           "lights (Light, PointLight, ...) are added, and light it alone when env is None. "
           "background: 'env' (default; 'black' for a captured light set), 'black' or 'alpha'. "
           "Values below zero (a model's reconstruction can undershoot) are clamped to 0 "
           "unless keep_negative.")
      .def("relight", &Relighter::relightLighting, py::arg("lighting"), py::kw_only(),
           py::arg("max_rank") = py::none(), py::arg("exposure") = 0.0, py::arg("background") = "",
           py::arg("out") = py::none(), py::arg("lights") = std::vector<LocalLight>{},
           py::arg("anchor_spread") = kAnchorSpreadTexels, py::arg("keep_negative") = false,
           "The same from a Lighting made by lighting(): the integration is not repeated.")
      .def("lighting", &Relighter::lighting, py::arg("env"), py::kw_only(), py::arg("yaw") = 0.0,
           py::arg("pitch") = 0.0, py::arg("roll") = 0.0, py::arg("fast_rotation") = false,
           "The environment under a rotation, integrated onto this file's lattice: a Lighting.")
      .def("relight_batch", &Relighter::relightBatch, py::arg("envs"), py::kw_only(),
           py::arg("rotations") = std::vector<std::tuple<double, double, double>>{{0, 0, 0}},
           py::arg("max_rank") = py::none(), py::arg("exposure") = 0.0, py::arg("background") = "",
           py::arg("fast_rotation") = false, py::arg("out") = py::none(),
           py::arg("lights") = std::vector<LocalLight>{},
           py::arg("anchor_spread") = kAnchorSpreadTexels, py::arg("light_positions") = py::none(),
           py::arg("keep_negative") = false,
           "Every environment under every (yaw, pitch, roll): N x H x W x C, environment-major; "
           "the lights are added to every frame. light_positions (F x K x 3, K lights): F "
           "times that, the lights moved to row f's positions for the f-th (light-major, as "
           "the CLI's --light-path).");
  m.def(
      "open", [](const std::string& path) { return Relighter(path); }, py::arg("path"),
      "Relighter(path)");
}

}  // namespace acpca::python
