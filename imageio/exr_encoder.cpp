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

/// Whether three equal bytes start at p (p + 2 < size).
bool tripleAt(const unsigned char* b, size_t p) {
  return b[p] == b[p + 1] && b[p + 1] == b[p + 2];
}

/// The first p in [from, limit) where three equal bytes start, else limit;
/// limit <= size. 32 positions at a time where the loads stay inside.
size_t firstTriple(const unsigned char* b, size_t size, size_t from, size_t limit) {
  size_t p = from;
#ifdef __AVX2__
  for (; p < limit && p + 34 <= size; p += 32) {
    const __m256i a = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + p));
    const __m256i n1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + p + 1));
    const __m256i n2 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + p + 2));
    const auto mask = static_cast<std::uint32_t>(_mm256_movemask_epi8(
        _mm256_and_si256(_mm256_cmpeq_epi8(a, n1), _mm256_cmpeq_epi8(n1, n2))));
    if (mask) return std::min(limit, p + static_cast<size_t>(__builtin_ctz(mask)));
  }
#endif
  for (; p < limit; ++p)
    if (p + 2 < size && tripleAt(b, p)) return p;
  return limit;
}

/// The end of the run of bytes equal to b[s], at most s + kMaxRun and size.
size_t runEnd(const unsigned char* b, size_t size, size_t s) {
  const size_t limit = std::min(size, s + kMaxRun);
  size_t e = s + 1;
#ifdef __AVX2__
  const __m256i value = _mm256_set1_epi8(static_cast<char>(b[s]));
  for (; e + 32 <= limit; e += 32) {
    const __m256i bytes = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + e));
    const auto equal =
        static_cast<std::uint32_t>(_mm256_movemask_epi8(_mm256_cmpeq_epi8(bytes, value)));
    if (equal != ~0u) return e + static_cast<size_t>(__builtin_ctz(~equal));
  }
#endif
  while (e < limit && b[e] == b[s]) ++e;
  return e;
}

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
    case ExrCodec::Zip:
      break;
  }
  return EXR_COMPRESSION_ZIP;
}

/// OpenEXR's default ZIP level (its C++ and core writers alike).
constexpr int kZipLevel = 4;

/// Writes the chunks of a part whose header is written.
exr_result_t writeChunks(exr_context_t context, const ExrPixels& p, ExrCodec codec,
                         const std::vector<int>& order) {
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

/// The header of a one-part scanline file; channels in the file's order.
exr_result_t writeHeader(exr_context_t context, const ExrPixels& p, ExrCodec codec,
                         const std::vector<int>& order,
                         const std::vector<std::pair<std::string, std::string>>& attributes) {
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
  return r ? r : exr_write_header(context);
}

}  // namespace

size_t exrRunLengthCode(const unsigned char* b, size_t size, unsigned char* out) {
  unsigned char* o = out;
  size_t s = 0;
  while (s < size) {
    size_t e = runEnd(b, size, s);
    if (e - s >= kMinRun) {
      *o++ = static_cast<unsigned char>(e - s - 1);
      *o++ = b[s];
    } else {
      e = firstTriple(b, size, e, std::min(size, s + kMaxLiteral));
      *o++ = static_cast<unsigned char>(-static_cast<int>(e - s));
      std::memcpy(o, b + s, e - s);
      o += e - s;
    }
    s = e;
  }
  return static_cast<size_t>(o - out);
}

bool writeExr(const std::string& file, const ExrPixels& p, ExrCodec codec,
              const std::vector<std::pair<std::string, std::string>>& attributes,
              std::string& error) {
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
  if (!r) r = writeHeader(context, p, codec, order, attributes);
  if (!r) r = writeChunks(context, p, codec, order);
  // exr_finish writes the offsets.
  const exr_result_t finished = context ? exr_finish(&context) : r;
  if (!r) r = finished;
  if (r && error.empty()) error = exr_get_default_error_message(r);
  return r == EXR_ERR_SUCCESS && writeWholeFile(file, encoded.data(), encoded.size(), error);
}

}  // namespace acpca
