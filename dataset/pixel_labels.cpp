#include "dataset/pixel_labels.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text.h"
#include "imageio/frame_metadata.h"
#include "imageio/image_file.h"
#include "imageio/image_output.h"
#include "imageio/npy_file.h"
#include "relight/image_composer.h"

namespace acpca {

namespace {

/// The mask picture's deflate level: written once a view, so small beats fast.
constexpr int kMaskPngLevel = 9;

constexpr std::array<Aov, 8> kAllAovs{Aov::Albedo,   Aov::Normal, Aov::Tangent, Aov::Depth,
                                      Aov::Position, Aov::Mask,   Aov::Object,  Aov::Shading};

std::vector<Aov> presetAovs(const std::string& name) {
  if (name == "all") return {kAllAovs.begin(), kAllAovs.end()};
  if (name == "intrinsic") return {Aov::Albedo, Aov::Mask, Aov::Shading};
  if (name == "geometry")
    return {Aov::Normal, Aov::Tangent, Aov::Depth, Aov::Position, Aov::Mask, Aov::Object};
  return {kAovNames.parse(name)};
}

/// What an AOV needs that older files lack, and since which versions.
bool fileGives(bool lightSet, const PixelDatasets& d, Aov aov) {
  switch (aov) {
    case Aov::Albedo:  // an imported image holds albedo and shading as one
      return !lightSet;
    case Aov::Normal:
      return d.normals;
    case Aov::Tangent:
      return d.tangents;
    case Aov::Depth:
    case Aov::Position:
      return d.positions;
    case Aov::Object:
      return d.objects;
    default:
      return true;
  }
}

/// A label's EXR channels: the names compositors expect.
std::vector<std::string> exrChannels(Aov aov) {
  switch (aov) {
    case Aov::Albedo:
      return {"albedo.R", "albedo.G", "albedo.B"};
    case Aov::Normal:
      return {"N.X", "N.Y", "N.Z"};
    case Aov::Tangent:
      return {"T.X", "T.Y", "T.Z"};
    case Aov::Depth:
      return {"Z"};
    case Aov::Position:
      return {"P.X", "P.Y", "P.Z"};
    case Aov::Mask:
      return {"A"};
    case Aov::Object:
      return {"object"};
    case Aov::Shading:
      break;
  }
  ACPCA_CHECK(false, "shading is a per-frame label");
  return {};
}

/// The per-pixel values of one layer, written at each row's pixel.
LabelLayer layerOf(const TransportHeader& h, Aov aov) {
  LabelLayer layer{aov, exrChannels(aov), {}};
  const size_t c = layer.channels.size();
  // Background: 0, and object -1 (no object).
  layer.values.assign(static_cast<size_t>(h.camera.size.pixels()) * c,
                      aov == Aov::Object ? -1.0f : 0.0f);
  const Vec3 eye = h.camera.eye, forward = h.camera.forward();
  for (long long r = 0; r < h.rows(); ++r) {
    float* out = &layer.values[static_cast<size_t>(h.pixels[r]) * c];
    const float* p = h.positions.empty() ? nullptr : &h.positions[3 * r];
    switch (aov) {
      case Aov::Albedo:  // premultiplied by coverage, as the relit image is
        for (int k = 0; k < 3; ++k) out[k] = h.coverage[r] * h.albedo[3 * r + k];
        break;
      case Aov::Normal:
        std::copy_n(&h.normals[3 * r], 3, out);
        break;
      case Aov::Tangent:  // the row's first traced camera sample's
        std::copy_n(&h.lamps.tangent[3 * static_cast<size_t>(h.lamps.sampleStart[r])], 3, out);
        break;
      case Aov::Depth:  // planar: along the view axis, not from the eye
        out[0] = static_cast<float>((Vec3(p[0], p[1], p[2]) - eye).dot(forward));
        break;
      case Aov::Position:
        std::copy_n(p, 3, out);
        break;
      case Aov::Mask:
        out[0] = h.coverage[r];
        break;
      case Aov::Object:
        out[0] = static_cast<float>(h.objects[r]);
        break;
      case Aov::Shading:
        break;
    }
  }
  return layer;
}

std::string joinedObjectNames(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) joined += (joined.empty() ? "" : "\n") + name;
  return joined;
}

/// Every layer's channels interleaved into one float EXR at `file`.
void encodeLabelsExr(const std::vector<LabelLayer>& layers, const TransportHeader& h,
                     const std::string& file, const std::string& path) {
  const size_t pixels = static_cast<size_t>(h.camera.size.pixels());
  std::vector<std::string> names;
  for (const LabelLayer& layer : layers)
    names.insert(names.end(), layer.channels.begin(), layer.channels.end());
  const size_t c = names.size();
  std::vector<float> values(pixels * c);
  size_t first = 0;
  for (const LabelLayer& layer : layers) {
    const size_t lc = layer.channels.size();
    for (size_t p = 0; p < pixels; ++p)
      std::copy_n(&layer.values[p * lc], lc, &values[p * c + first]);
    first += lc;
  }
  // The channels named A and Z are the file's alpha and depth.
  ImageWriteSpec spec{h.camera.size.width, h.camera.size.height, static_cast<int>(c),
                      PixelType::Float, names};
  spec.textAttributes = {{"compression", "zip"}, {"DateTime", ""}};  // equal inputs, equal bytes
  if (std::any_of(layers.begin(), layers.end(),
                  [](const LabelLayer& l) { return l.aov == Aov::Object; }))
    spec.textAttributes.emplace_back("objects", joinedObjectNames(h.objectNames));
  // Values, not colour; the view's camera; the tool (docs/formats.md, "Frame metadata").
  FrameMetadata metadata;
  metadata.values = FrameMetadata::Values::Data;
  if (!h.isLightSet()) metadata.setCamera(h.camera.worldToCamera(), h.camera.worldToNdc());
  metadata.fields = {{"scene", h.scene}, {"version", ACPCA_VERSION}};
  spec.metadata = &metadata;
  writeImageFile(file, spec, values.data(), path, "the labels");
}

void encodeLayerNpy(const LabelLayer& layer, const TransportHeader& h, const std::string& file,
                    const std::string& path) {
  std::vector<size_t> shape{static_cast<size_t>(h.camera.size.height),
                            static_cast<size_t>(h.camera.size.width)};
  if (layer.channels.size() > 1) shape.push_back(layer.channels.size());
  if (layer.aov != Aov::Object) return writeNpy(file, path, shape, layer.values.data());
  std::vector<std::int32_t> ids(layer.values.begin(), layer.values.end());
  writeNpy(file, path, shape, ids.data());
}

}  // namespace

std::vector<Aov> parseAovList(const std::string& text) {
  std::vector<bool> chosen(kAllAovs.size(), false);
  for (const std::string& name : splitText(text, ',')) {
    if (name.empty()) throw ParameterError("AOV", text, "has an empty name in the list");
    for (Aov aov : presetAovs(name)) chosen[static_cast<size_t>(aov)] = true;
  }
  std::vector<Aov> aovs;
  for (Aov aov : kAllAovs)
    if (chosen[static_cast<size_t>(aov)]) aovs.push_back(aov);
  return aovs;
}

std::vector<Aov> availableAovs(const TransportHeader& header, const PixelDatasets& datasets) {
  std::vector<Aov> aovs;
  for (Aov aov : kAllAovs)
    if (fileGives(header.isLightSet(), datasets, aov)) aovs.push_back(aov);
  return aovs;
}

std::vector<Aov> availableAovs(const TransportHeader& header) {
  return availableAovs(header, PixelDatasets::of(header));
}

void requireAovs(const TransportHeader& header, const std::vector<Aov>& aovs,
                 const std::string& path, bool model) {
  for (Aov aov : aovs) {
    if (fileGives(header.isLightSet(), PixelDatasets::of(header), aov)) continue;
    if (header.isLightSet())
      throw UserError(concat(path, ": cannot give the '", kAovNames.name(aov),
                             "' label: a captured light set holds images, not the geometry or "
                             "albedo under them (its labels are mask and shading)"));
    const std::string remedy =
        model ? "compress (or build) it again with this version, from a transport made by it"
              : "run precompute again with this version";
    throw UserError(concat(path, ": cannot give the '", kAovNames.name(aov),
                           "' label: the file was made before it kept each pixel's ",
                           aov == Aov::Normal    ? "normal"
                           : aov == Aov::Tangent ? "tangent"
                           : aov == Aov::Object  ? "object"
                                                 : "position",
                           "; ", remedy));
  }
}

std::vector<LabelLayer> viewLabels(const TransportHeader& header, const std::vector<Aov>& aovs) {
  std::vector<LabelLayer> layers;
  for (Aov aov : aovs)
    if (aov != Aov::Shading) layers.push_back(layerOf(header, aov));
  return layers;
}

std::vector<std::string> writeViewLabels(const std::vector<LabelLayer>& layers,
                                         const TransportHeader& header, const std::string& stem,
                                         LabelFormat format) {
  std::vector<std::unique_ptr<AtomicOutput>> files;
  std::vector<std::string> paths;
  if (layers.empty()) return paths;
  if (format != LabelFormat::Npy) {
    files.push_back(std::make_unique<AtomicOutput>(stem + ".exr"));
    encodeLabelsExr(layers, header, files.back()->tempPath(), files.back()->finalPath());
  }
  if (format != LabelFormat::Exr)
    for (const LabelLayer& layer : layers) {
      files.push_back(
          std::make_unique<AtomicOutput>(concat(stem, "_", kAovNames.name(layer.aov), ".npy")));
      encodeLayerNpy(layer, header, files.back()->tempPath(), files.back()->finalPath());
    }
  // Coverage as an 8-bit picture, round(255 A): the mask image loaders such
  // as nerfstudio read (transforms.json's mask_path).
  for (const LabelLayer& layer : layers)
    if (layer.aov == Aov::Mask) {
      std::vector<unsigned char> codes(layer.values.size());
      std::transform(layer.values.begin(), layer.values.end(), codes.begin(), [](float a) {
        return static_cast<unsigned char>(std::lround(255 * std::clamp(a, 0.0f, 1.0f)));
      });
      files.push_back(std::make_unique<AtomicOutput>(stem + "_mask.png"));
      encodePng8(header.camera.size.width, header.camera.size.height, 1, codes.data(),
                 files.back()->tempPath(), files.back()->finalPath(), kMaskPngLevel);
    }
  for (auto& file : files) {
    file->commit();
    paths.push_back(file->finalPath());
  }
  return paths;
}

void frameShading(const TransportHeader& header, const float* frame, const float* background,
                  int channels, float* shading, bool keepNegative) {
  std::fill_n(shading, static_cast<size_t>(header.camera.size.pixels()) * 3, 0.0f);
  for (long long r = 0; r < header.rows(); ++r) {
    const size_t pixel = static_cast<size_t>(header.pixels[r]);
    for (int k = 0; k < 3; ++k) {
      const size_t at = pixel * channels + k;
      const float weight = header.coverage[r] * header.albedo[3 * r + k];
      const float value = weight > 0 ? (frame[at] - background[at]) / weight : 0.0f;
      shading[pixel * 3 + k] = keepNegative ? value : std::max(value, 0.0f);
    }
  }
}

}  // namespace acpca
