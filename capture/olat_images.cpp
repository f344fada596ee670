#include "capture/olat_images.h"

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/error.h"
#include "core/srgb.h"
#include "imageio/image_file.h"

namespace acpca {

namespace {

/// Decoding tables of every 8- and 16-bit code: exact, and a lookup per value.
const std::vector<float>& codeTable(int bits, bool srgb) {
  static const auto make = [](int codes, bool encoded) {
    std::vector<float> t(codes);
    for (int i = 0; i < codes; ++i) {
      const double v = static_cast<double>(i) / (codes - 1);
      t[i] = static_cast<float>(encoded ? srgbToLinear(v) : v);
    }
    return t;
  };
  static const std::array<std::vector<float>, 4> tables{make(256, false), make(256, true),
                                                        make(65536, false), make(65536, true)};
  return tables[(bits == 16 ? 2 : 0) + (srgb ? 1 : 0)];
}

/// A light stage's folder can hold more images than the default limit of
/// open files (1,024): ask for the hard limit.
void allowOpenFiles(size_t files) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur >= files + 64) return;
  limit.rlim_cur = std::min<rlim_t>(limit.rlim_max, files + 64);
  setrlimit(RLIMIT_NOFILE, &limit);
}

class ImageFile {
 public:
  ImageFile(const std::string& path, TransferFunction transfer) : path_(path) {
    std::string error;
    in_ = openImage(path, error, {.unassociatedAlpha = true});  // colour as stored, not times alpha
    if (!in_) throw UserError(concat(path, ": cannot read the image: ", error));
    const ImageHeader& spec = in_->header();
    if (spec.width < 1 || spec.height < 1 || spec.depth != 1 || spec.channels < 1 ||
        spec.width > kMaxImageSide || spec.height > kMaxImageSide)
      throw UserError(concat(path, ": image size ", spec.width, "x", spec.height, " (",
                             spec.channels, " channels) is out of range"));
    size_ = {spec.width, spec.height};
    channels_ = spec.channels >= 3 ? 3 : 1;
    bits_ = spec.stored == StoredValues::UInt8 ? 8 : spec.stored == StoredValues::UInt16 ? 16 : 0;
    srgb_ =
        transfer == TransferFunction::Srgb || (transfer == TransferFunction::Auto && bits_ != 0);
  }

  ImageSize size() const { return size_; }
  const std::string& path() const { return path_; }
  long long saturated() const { return saturated_; }

  void readBand(int y0, int y1, float* out) {
    const size_t values = static_cast<size_t>(y1 - y0) * size_.width * channels_;
    const PixelType type = bits_ == 8    ? PixelType::UInt8
                           : bits_ == 16 ? PixelType::UInt16
                                         : PixelType::Float;
    raw_.resize(values * pixelTypeBytes(type));
    if (!in_->readRows(y0, y1, 0, channels_, type, raw_.data()))
      throw UserError(concat(path_, ": cannot read rows ", y0, " to ", y1 - 1, ": ", in_->error()));
    const size_t pixels = static_cast<size_t>(y1 - y0) * size_.width;
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < 3; ++c)
        out[3 * p + c] = value(p * channels_ + (channels_ == 3 ? c : 0), y0, p);
  }

 private:
  float value(size_t i, int y0, size_t pixel) {
    if (bits_ == 8 || bits_ == 16) {
      const unsigned code =
          bits_ == 8 ? raw_[i] : reinterpret_cast<const std::uint16_t*>(raw_.data())[i];
      if (code == (bits_ == 8 ? 255u : 65535u)) ++saturated_;
      return codeTable(bits_, srgb_)[code];
    }
    const float v = reinterpret_cast<const float*>(raw_.data())[i];
    if (!std::isfinite(v))
      throw UserError(concat(path_, ": pixel (", pixel % size_.width, ", ",
                             y0 + pixel / size_.width, ") is not a finite number"));
    return srgb_ ? static_cast<float>(srgbToLinear(v)) : v;
  }

  std::string path_;
  std::unique_ptr<ImageReader> in_;
  ImageSize size_;
  int channels_ = 3, bits_ = 0;
  bool srgb_ = false;
  std::vector<unsigned char> raw_;
  long long saturated_ = 0;
};

class ImageFiles : public OlatImages {
 public:
  ImageFiles(const std::vector<std::string>& paths, TransferFunction transfer) {
    allowOpenFiles(paths.size());
    for (const std::string& path : paths) {
      files_.push_back(std::make_unique<ImageFile>(path, transfer));
      const ImageSize s = files_.back()->size(), first = files_.front()->size();
      if (s.width != first.width || s.height != first.height)
        throw UserError(concat(path, ": ", s.width, "x", s.height, ", but ", paths.front(), " is ",
                               first.width, "x", first.height, " (every image must be one size)"));
    }
  }
  int count() const override { return static_cast<int>(files_.size()); }
  ImageSize size() const override { return files_.front()->size(); }
  void readBand(int k, int y0, int y1, float* out) override { files_[k]->readBand(y0, y1, out); }
  std::string name(int k) const override { return files_[k]->path(); }
  long long saturated(int k) const override { return files_[k]->saturated(); }

 private:
  std::vector<std::unique_ptr<ImageFile>> files_;
};

class ImagesInMemory : public OlatImages {
 public:
  ImagesInMemory(const float* values, int count, ImageSize size)
      : values_(values), count_(count), size_(size) {}
  int count() const override { return count_; }
  ImageSize size() const override { return size_; }
  void readBand(int k, int y0, int y1, float* out) override {
    const size_t perImage = static_cast<size_t>(size_.pixels()) * 3;
    const float* from = values_ + k * perImage + static_cast<size_t>(y0) * size_.width * 3;
    const size_t n = static_cast<size_t>(y1 - y0) * size_.width * 3;
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(from[i]))
        throw UserError(concat(name(k), ": pixel (", (i / 3) % size_.width, ", ",
                               y0 + (i / 3) / size_.width, ") is not a finite number"));
      out[i] = from[i];
    }
  }
  std::string name(int k) const override { return concat("images[", k, "]"); }
  long long saturated(int) const override { return 0; }

 private:
  const float* values_;
  int count_;
  ImageSize size_;
};

}  // namespace

std::unique_ptr<OlatImages> openImageFiles(const std::vector<std::string>& paths,
                                           TransferFunction transfer) {
  ACPCA_CHECK(!paths.empty(), "no images");
  return std::make_unique<ImageFiles>(paths, transfer);
}

std::unique_ptr<OlatImages> imagesInMemory(const float* values, int count, ImageSize size) {
  ACPCA_CHECK(count >= 1 && size.pixels() > 0, count, " images of ", size.pixels(), " pixels");
  return std::make_unique<ImagesInMemory>(values, count, size);
}

std::vector<float> readMask(const std::string& path, ImageSize size) {
  std::string error;
  auto in = openImage(path, error);
  if (!in) throw UserError(concat(path, ": cannot read the mask: ", error));
  const ImageHeader& spec = in->header();
  if (spec.width != size.width || spec.height != size.height)
    throw UserError(concat(path, ": the mask is ", spec.width, "x", spec.height,
                           ", the images are ", size.width, "x", size.height));
  // A mask with alpha keeps it there; else its first channel.
  const int channel = spec.alphaChannel >= 0 ? spec.alphaChannel : 0;
  std::vector<float> mask(static_cast<size_t>(size.pixels()));
  if (!in->readImage(channel, channel + 1, PixelType::Float, mask.data()))
    throw UserError(concat(path, ": cannot read the mask: ", in->error()));
  for (float& m : mask) {
    if (!std::isfinite(m))
      throw UserError(concat(path, ": the mask holds a value that is not finite"));
    m = std::clamp(m, 0.0f, 1.0f);
  }
  return mask;
}

}  // namespace acpca
