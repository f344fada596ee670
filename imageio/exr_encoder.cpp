#include "imageio/exr_encoder.h"

#include <OpenEXR/openexr.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <type_traits>
#include <vector>
#ifdef __AVX2__
#include <immintrin.h>
#endif

#include "imageio/whole_file.h"
#include "imageio/zlib_stream.h"

namespace acpca {

namespace {

// OpenEXR's run-length code: a run of 3 to 128 equal bytes is a count byte
// (length - 1) and the byte; anything else goes as literals, a count byte
// -(1 to 127) and the bytes.
constexpr size_t kMinRun = 3, kMaxRun = 128, kMaxLiteral = 127;

/// A chunk's bytes as bit masks, 64 positions a word: bit p of `next` is
/// set when b[p + 1] == b[p]. A run is a stretch of set bits, and three
/// equal bytes start at p where bits p and p + 1 are both set; the coder
/// then finds each run's end and each literal's end in a word or three,
/// where comparing byte by byte missed a branch at every change.
class EqualNeighbours {
 public:
  void build(const unsigned char* b, size_t size) {
    words_.assign(size / 64 + 2, 0);  // a zero word past the end for triples()
    size_t p = 0;
#ifdef __AVX2__
    for (; p + 33 <= size; p += 32) {
      const __m256i here = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + p));
      const __m256i next = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + p + 1));
      const auto equal =
          static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(here, next)));
      words_[p / 64] |= static_cast<std::uint64_t>(equal) << (p % 64);  // p % 64 is 0 or 32
    }
#endif
    for (; p + 1 < size; ++p)
      words_[p / 64] |= static_cast<std::uint64_t>(b[p + 1] == b[p]) << (p % 64);
  }
  /// The first p in [from, limit) where b[p + 1] != b[p], else limit (limit < size).
  size_t firstChange(size_t from, size_t limit) const {
    return firstSet(from, limit, [&](size_t w) { return ~words_[w]; });
  }
  /// The first p in [from, limit) where three equal bytes start, else limit.
  size_t firstTriple(size_t from, size_t limit) const {
    return firstSet(from, limit,
                    [&](size_t w) { return words_[w] & (words_[w] >> 1 | words_[w + 1] << 63); });
  }

 private:
  template <typename Word>
  static size_t firstSet(size_t from, size_t limit, const Word& word) {
    if (from >= limit) return limit;
    size_t w = from / 64;
    std::uint64_t bits = word(w) & (~std::uint64_t{0} << (from % 64));
    while (bits == 0) {
      if (++w * 64 >= limit) return limit;
      bits = word(w);
    }
    return std::min(limit, w * 64 + static_cast<size_t>(std::countr_zero(bits)));
  }
  std::vector<std::uint64_t> words_;
};

/// OpenEXR's preparation of a chunk for RLE and ZIP: even bytes then odd
/// bytes, each byte then replaced by its difference from the one before
/// (plus 128, modulo 256).
void reorderAndPredict(const unsigned char* in, size_t size, unsigned char* out) {
  if (size == 0) return;
  const size_t half = (size + 1) / 2;
  unsigned char* evens = out;
  unsigned char* odds = out + half;
  evens[0] = in[0];
  for (size_t i = 1; i < half; ++i)
    evens[i] = static_cast<unsigned char>(in[2 * i] - in[2 * i - 2] + 128);
  if (size < 2) return;
  odds[0] = static_cast<unsigned char>(in[1] - in[2 * half - 2] + 128);
  for (size_t i = 1; i < size / 2; ++i)
    odds[i] = static_cast<unsigned char>(in[2 * i + 1] - in[2 * i - 1] + 128);
}

/// Each row of the chunk, channel by channel in the file's (sorted) order.
void packRows(const ExrPixels& p, const std::vector<int>& order, int y0, int y1,
              unsigned char* out) {
  const size_t channels = p.channelNames.size();
  const size_t width = static_cast<size_t>(p.width);
  const auto pack = [&](const auto* values) {
    using Value = std::remove_const_t<std::remove_pointer_t<decltype(values)>>;
    auto* o = reinterpret_cast<Value*>(out);
    for (int y = y0; y < y1; ++y)
      for (int source : order) {
        const Value* v = values + static_cast<size_t>(y) * width * channels + source;
        for (size_t x = 0; x < width; ++x) o[x] = v[x * channels];
        o += width;
      }
  };
  // EXR stores values little-endian, as they are in memory here.
  static_assert(std::endian::native == std::endian::little);
  if (p.isFloat)
    pack(static_cast<const float*>(p.values));
  else
    pack(static_cast<const std::uint16_t*>(p.values));
}

/// packRows then reorderAndPredict in one pass, for half values: the
/// chunk's low bytes then its high bytes (`split`, scratch of the chunk's
/// size), then each byte's difference from the one before (+128) in `out`,
/// a loop the compiler vectorizes.
void prepareHalfRows(const ExrPixels& p, const std::vector<int>& order, int y0, int y1,
                     unsigned char* split, unsigned char* out) {
  const size_t channels = p.channelNames.size();
  const size_t width = static_cast<size_t>(p.width);
  const size_t halves = width * channels * static_cast<size_t>(y1 - y0);
  const auto* values = static_cast<const std::uint16_t*>(p.values);
  unsigned char* low = split;
  unsigned char* high = split + halves;
  for (int y = y0; y < y1; ++y)
    for (int source : order) {
      const std::uint16_t* v = values + static_cast<size_t>(y) * width * channels + source;
      for (size_t x = 0; x < width; ++x) {
        const std::uint16_t h = v[x * channels];
        low[x] = static_cast<unsigned char>(h);
        high[x] = static_cast<unsigned char>(h >> 8);
      }
      low += width, high += width;
    }
  if (halves == 0) return;
  out[0] = split[0];
  for (size_t i = 1; i < 2 * halves; ++i)
    out[i] = static_cast<unsigned char>(split[i] - split[i - 1] + 128);
}

exr_compression_t compressionOf(ExrCodec codec) {
  switch (codec) {
    case ExrCodec::None:
      return EXR_COMPRESSION_NONE;
    case ExrCodec::Rle:
      return EXR_COMPRESSION_RLE;
    case ExrCodec::Zips:
      return EXR_COMPRESSION_ZIPS;
    case ExrCodec::Piz:
      return EXR_COMPRESSION_PIZ;
    case ExrCodec::Zip:
      break;
  }
  return EXR_COMPRESSION_ZIP;
}

/// OpenEXR's default ZIP level (its C++ and core writers alike).
constexpr int kZipLevel = 4;

/// PIZ chunks by OpenEXR's own encode pipeline (its wavelet and Huffman
/// code), reading each channel where it lies in the interleaved pixels.
exr_result_t writePizChunks(exr_context_t context, const ExrPixels& p,
                            const std::vector<int>& order) {
  const int32_t valueBytes = p.isFloat ? 4 : 2;
  const int32_t pixelBytes = valueBytes * static_cast<int32_t>(order.size());
  const auto* values = static_cast<const uint8_t*>(p.values);
  exr_encode_pipeline_t pipeline{};
  bool started = false;
  exr_result_t r = EXR_ERR_SUCCESS;
  for (int y = 0; y < p.height && !r;) {
    exr_chunk_info_t chunk{};
    r = exr_write_scanline_chunk_info(context, 0, y, &chunk);
    if (!r)
      r = started ? exr_encoding_update(context, 0, &chunk, &pipeline)
                  : exr_encoding_initialize(context, 0, &chunk, &pipeline);
    if (r) break;
    for (int16_t c = 0; c < pipeline.channel_count; ++c) {
      exr_coding_channel_info_t& channel = pipeline.channels[c];
      channel.encode_from_ptr = values +
                                (static_cast<size_t>(chunk.start_y) * p.width) * pixelBytes +
                                static_cast<size_t>(order[c]) * valueBytes;
      channel.user_pixel_stride = pixelBytes;
      channel.user_line_stride = pixelBytes * p.width;
      channel.user_bytes_per_element = static_cast<int16_t>(valueBytes);
      channel.user_data_type = p.isFloat ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF;
    }
    if (!started) r = exr_encoding_choose_default_routines(context, 0, &pipeline);
    started = true;
    if (!r) r = exr_encoding_run(context, 0, &pipeline);
    y = chunk.start_y + chunk.height;
  }
  if (started) {
    const exr_result_t destroyed = exr_encoding_destroy(context, &pipeline);
    if (!r) r = destroyed;
  }
  return r;
}

/// Writes the chunks of a part whose header is written.
exr_result_t writeChunks(exr_context_t context, const ExrPixels& p, ExrCodec codec,
                         const std::vector<int>& order) {
  if (codec == ExrCodec::Piz) return writePizChunks(context, p, order);
  int32_t linesPerChunk = 1;
  if (const exr_result_t r = exr_get_scanlines_per_chunk(context, 0, &linesPerChunk)) return r;
  const size_t valueBytes = p.isFloat ? 4 : 2;
  const size_t lineBytes = static_cast<size_t>(p.width) * p.channelNames.size() * valueBytes;
  std::vector<unsigned char> packed(lineBytes * linesPerChunk), prepared(packed.size());
  std::vector<unsigned char> coded;
  for (int y = 0; y < p.height; y += linesPerChunk) {
    const int y1 = std::min(p.height, y + linesPerChunk);
    const size_t bytes = lineBytes * (y1 - y);
    const unsigned char* chunk = packed.data();
    size_t chunkBytes = bytes;
    if (codec == ExrCodec::None) packRows(p, order, y, y1, packed.data());
    if (codec != ExrCodec::None) {
      if (p.isFloat) {
        packRows(p, order, y, y1, packed.data());
        reorderAndPredict(packed.data(), bytes, prepared.data());
      } else {
        prepareHalfRows(p, order, y, y1, packed.data(), prepared.data());
      }
      coded.clear();
      if (codec == ExrCodec::Rle) {
        coded.resize(bytes + bytes / 64 + 2);
        coded.resize(exrRunLengthCode(prepared.data(), bytes, coded.data()));
      } else {
        appendZlibStream(prepared.data(), bytes, kZipLevel, coded);
      }
      // A chunk that would not shrink is stored as it is (readers tell by its size).
      if (coded.size() < bytes)
        chunk = coded.data(), chunkBytes = coded.size();
      else if (!p.isFloat)
        packRows(p, order, y, y1, packed.data());  // it held the split bytes
    }
    if (const exr_result_t r = exr_write_scanline_chunk(context, 0, y, chunk, chunkBytes)) return r;
  }
  return EXR_ERR_SUCCESS;
}

/// Appends the numbers of `value` (a number, or lists of them at any depth)
/// to `out`; false for anything else or an empty list.
bool flattenNumbers(const nlohmann::json& value, std::vector<float>& out) {
  if (value.is_number()) {
    out.push_back(value.get<float>());
    return true;
  }
  if (!value.is_array() || value.empty()) return false;
  for (const nlohmann::json& v : value)
    if (!flattenNumbers(v, out)) return false;
  return true;
}

/// A frame's colour space, camera and fields (frame_metadata.h) as typed attributes.
exr_result_t writeFrameMetadata(exr_context_t context, int part, const FrameMetadata& m) {
  const auto& c = kRec709Chromaticities;
  const exr_attr_chromaticities_t chromaticities{c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]};
  exr_result_t r = exr_attr_set_chromaticities(context, part, "chromaticities", &chromaticities);
  if (!r) r = exr_attr_set_string(context, part, "colorInteropID", m.colorInteropId());
  for (const auto& [name, matrix] :
       {std::pair{"worldToCamera", &m.worldToCamera}, std::pair{"worldToNDC", &m.worldToNdc}})
    if (!r && *matrix) {
      exr_attr_m44f_t value;
      std::copy((*matrix)->begin(), (*matrix)->end(), value.m);
      r = exr_attr_set_m44f(context, part, name, &value);
    }
  for (const auto& [key, value] : m.fields.items()) {
    if (r) break;
    const std::string name = kFrameFieldPrefix + key;
    std::vector<float> floats;
    if (value.is_null()) continue;  // absent, as a reader of the header finds it
    if (value.is_string()) {
      r = exr_attr_set_string(context, part, name.c_str(), value.get<std::string>().c_str());
    } else if (value.is_number()) {
      r = exr_attr_set_double(context, part, name.c_str(), value.get<double>());
    } else if (value.is_array() && flattenNumbers(value, floats)) {
      r = exr_attr_set_float_vector(context, part, name.c_str(),
                                    static_cast<int32_t>(floats.size()), floats.data());
    } else {
      r = exr_attr_set_string(context, part, name.c_str(), value.dump().c_str());
    }
  }
  return r;
}

/// The header of a one-part scanline file; channels in the file's order.
exr_result_t writeHeader(exr_context_t context, const ExrPixels& p, ExrCodec codec,
                         const std::vector<int>& order,
                         const std::vector<std::pair<std::string, std::string>>& attributes,
                         const FrameMetadata* metadata) {
  int part = 0;
  exr_result_t r = exr_add_part(context, "", EXR_STORAGE_SCANLINE, &part);
  if (!r)
    r = exr_initialize_required_attr_simple(context, part, p.width, p.height, compressionOf(codec));
  for (size_t k = 0; k < order.size() && !r; ++k)
    r = exr_add_channel(context, part, p.channelNames[order[k]].c_str(),
                        p.isFloat ? EXR_PIXEL_FLOAT : EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC,
                        1, 1);
  for (const auto& [name, value] : attributes)
    if (!r) r = exr_attr_set_string(context, part, name.c_str(), value.c_str());
  if (!r && metadata) r = writeFrameMetadata(context, part, *metadata);
  return r ? r : exr_write_header(context);
}

}  // namespace

size_t exrRunLengthCode(const unsigned char* b, size_t size, unsigned char* out) {
  thread_local EqualNeighbours neighbours;
  EqualNeighbours& equal = neighbours;  // the thread's address found once
  equal.build(b, size);
  unsigned char* o = out;
  size_t s = 0;
  while (s < size) {
    // The run of bytes equal to b[s]: it ends after the first change.
    const size_t limit = std::min(size, s + kMaxRun);
    size_t e = equal.firstChange(s, limit - 1) + 1;
    if (e - s >= kMinRun) {
      *o++ = static_cast<unsigned char>(e - s - 1);
      *o++ = b[s];
    } else {
      e = equal.firstTriple(e, std::min(size, s + kMaxLiteral));
      *o++ = static_cast<unsigned char>(-static_cast<int>(e - s));
      // Away from the end, a literal's 127 bytes at most go as 128 in a few
      // wide moves (no call); `out`'s room covers what lands past it.
      if (s + kMaxRun <= size)
        std::memcpy(o, b + s, kMaxRun);
      else
        std::memcpy(o, b + s, e - s);
      o += e - s;
    }
    s = e;
  }
  return static_cast<size_t>(o - out);
}

bool writeExr(const std::string& file, const ExrPixels& p, ExrCodec codec,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              const FrameMetadata* metadata, std::string& error) {
  // EXR lists channels sorted by name; `order` holds their interleaved indices.
  std::vector<int> order(p.channelNames.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return p.channelNames[a] < p.channelNames[b]; });
  // Encoded into memory (kept from call to call on each thread), then
  // written to the file in one call (whole_file.h).
  struct Stream {
    std::string* error;
    std::vector<unsigned char>* bytes;
  };
  thread_local std::vector<unsigned char> encoded;
  encoded.clear();
  Stream stream{&error, &encoded};
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &stream;
  init.error_handler_fn = [](exr_const_context_t context, exr_result_t code, const char* message) {
    void* data = nullptr;
    if (exr_get_user_data(context, &data) == EXR_ERR_SUCCESS && data)
      *static_cast<Stream*>(data)->error = message ? message : exr_get_default_error_message(code);
  };
  init.write_fn = [](exr_const_context_t, void* data, const void* buffer, uint64_t size,
                     uint64_t offset, exr_stream_error_func_ptr_t) -> int64_t {
    std::vector<unsigned char>& bytes = *static_cast<Stream*>(data)->bytes;
    if (offset + size > bytes.size()) bytes.resize(offset + size);
    std::memcpy(bytes.data() + offset, buffer, size);
    return static_cast<int64_t>(size);
  };
  exr_context_t context = nullptr;
  exr_result_t r = exr_start_write(&context, file.c_str(), EXR_WRITE_FILE_DIRECTLY, &init);
  if (!r) r = writeHeader(context, p, codec, order, attributes, metadata);
  if (!r) r = writeChunks(context, p, codec, order);
  // exr_finish writes the offsets.
  const exr_result_t finished = context ? exr_finish(&context) : r;
  if (!r) r = finished;
  if (r && error.empty()) error = exr_get_default_error_message(r);
  return r == EXR_ERR_SUCCESS && writeWholeFile(file, encoded.data(), encoded.size(), error);
}

}  // namespace acpca
