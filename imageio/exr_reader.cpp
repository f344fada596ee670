#include "imageio/exr_reader.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/openexr.h>

#include <array>
#include <exception>
#include <vector>

namespace acpca {

namespace {

/// The channels read here, in OpenImageIO's order.
constexpr std::array<const char*, 5> kOrder = {"Y", "R", "G", "B", "A"};
/// Larger images are left to OpenImageIO (and environment maps refused).
constexpr long long kMaxPixels = 1LL << 28;

class OpenExrReader : public ImageReader {
 public:
  OpenExrReader(std::unique_ptr<Imf::InputFile> file, ImageHeader header)
      : file_(std::move(file)), header_(std::move(header)) {}

  const ImageHeader& header() const override { return header_; }

  bool readImage(int firstChannel, int endChannel, PixelType type, void* out) override {
    return readRows(0, header_.height, firstChannel, endChannel, type, out);
  }

  bool readRows(int y0, int y1, int firstChannel, int endChannel, PixelType type,
                void* out) override {
    if (type != PixelType::Float && type != PixelType::Half)
      return fail("an EXR is read here as half or float values");
    if (y0 < 0 || y1 > header_.height || y0 >= y1 || firstChannel < 0 ||
        endChannel > header_.channels || firstChannel >= endChannel)
      return fail("rows or channels out of range");
    const size_t bytes = pixelTypeBytes(type), channels = endChannel - firstChannel;
    const size_t pixelStride = channels * bytes, rowStride = header_.width * pixelStride;
    try {
      Imf::FrameBuffer frame;
      for (int c = firstChannel; c < endChannel; ++c)
        frame.insert(header_.channelNames[c],
                     Imf::Slice::Make(type == PixelType::Float ? Imf::FLOAT : Imf::HALF,
                                      static_cast<char*>(out) + (c - firstChannel) * bytes,
                                      IMATH_NAMESPACE::V2i(0, y0), header_.width, y1 - y0,
                                      pixelStride, rowStride));
      file_->setFrameBuffer(frame);
      file_->readPixels(y0, y1 - 1);
      return true;
    } catch (const std::exception& e) {
      return fail(e.what());
    }
  }

  std::string error() override { return std::exchange(error_, {}); }

 private:
  bool fail(const std::string& reason) {
    if (error_.empty()) error_ = reason;
    return false;
  }

  std::unique_ptr<Imf::InputFile> file_;
  ImageHeader header_;
  std::string error_;
};

/// The header of a file read here; false when it is not one.
bool describe(const Imf::Header& h, ImageHeader& header) {
  const IMATH_NAMESPACE::Box2i& data = h.dataWindow();
  if (data != h.displayWindow() || data.min.x != 0 || data.min.y != 0) return false;
  int count = 0;
  for (auto c = h.channels().begin(); c != h.channels().end(); ++c) {
    const Imf::Channel& channel = c.channel();
    if (channel.xSampling != 1 || channel.ySampling != 1 ||
        (channel.type != Imf::HALF && channel.type != Imf::FLOAT))
      return false;
    ++count;
  }
  for (const char* name : kOrder)
    if (h.channels().findChannel(name)) header.channelNames.push_back(name);
  if (header.channelNames.empty() || static_cast<int>(header.channelNames.size()) != count)
    return false;
  // Y beside colours: OpenImageIO's to order.
  if (header.channelNames[0] == "Y" && count > 2) return false;
  header.width = data.max.x + 1;
  header.height = data.max.y + 1;
  header.channels = count;
  header.stored = StoredValues::FloatingPoint;
  header.alphaChannel = header.channelNames.back() == "A" ? count - 1 : -1;
  header.colorSpace = "Linear";  // as OpenImageIO names an EXR's
  return true;
}

/// Whether OpenEXR's core parser (bounded, hardened against broken files)
/// finds a header whose windows and channels could be one read here: the
/// C++ library then allocates by those sizes.
bool plausibleHeader(const std::string& path) {
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};  // silent
  exr_context_t context = nullptr;
  bool plausible = false;
  if (exr_start_read(&context, path.c_str(), &init) == EXR_ERR_SUCCESS) {
    exr_attr_box2i_t data, display;
    const exr_attr_chlist_t* channels = nullptr;
    plausible =
        !exr_get_data_window(context, 0, &data) && !exr_get_display_window(context, 0, &display) &&
        !exr_get_channels(context, 0, &channels) && channels && channels->num_channels >= 1 &&
        channels->num_channels <= 4 && data.min.x == 0 && data.min.y == 0 && data.max.x >= 0 &&
        data.max.y >= 0 && (data.max.x + 1LL) * (data.max.y + 1LL) <= kMaxPixels;
  }
  if (context) exr_finish(&context);
  return plausible;
}

}  // namespace

std::unique_ptr<ImageReader> openExrDirectly(const std::string& path) {
  if (!plausibleHeader(path)) return nullptr;
  try {
    auto file = std::make_unique<Imf::InputFile>(path.c_str());
    ImageHeader header;
    if (!describe(file->header(), header)) return nullptr;
    return std::make_unique<OpenExrReader>(std::move(file), std::move(header));
  } catch (const std::exception&) {
    return nullptr;  // OpenImageIO tries, and says what is wrong
  }
}

}  // namespace acpca
