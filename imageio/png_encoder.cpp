#include "imageio/png_encoder.h"

#include <libdeflate.h>

#include <cstdlib>
#include <cstring>

#include "core/error.h"
#include "imageio/zlib_stream.h"

namespace acpca {

namespace {

constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
enum Filter : unsigned char { kSub = 1, kPaeth = 4 };

void appendBigEndian(std::vector<unsigned char>& out, std::uint32_t v) {
  const unsigned char bytes[4] = {
      static_cast<unsigned char>(v >> 24), static_cast<unsigned char>(v >> 16),
      static_cast<unsigned char>(v >> 8), static_cast<unsigned char>(v)};
  out.insert(out.end(), bytes, bytes + 4);
}

/// A chunk: length, type, data, CRC-32 of type and data.
void appendChunk(std::vector<unsigned char>& out, const char* type, const unsigned char* data,
                 size_t size) {
  appendBigEndian(out, static_cast<std::uint32_t>(size));
  const size_t typeAt = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data, data + size);
  appendBigEndian(out, libdeflate_crc32(0, out.data() + typeAt, 4 + size));
}

unsigned char paethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return static_cast<unsigned char>(pa <= pb && pa <= pc ? a : pb <= pc ? b : c);
}

/// One row's bytes filtered (PNG 9.2) into `out`, `bpp` bytes a pixel; `up`
/// is the row above, null for the first.
void filterRow(Filter filter, const unsigned char* row, const unsigned char* up, size_t bytes,
               int bpp, unsigned char* out) {
  if (filter == kSub) {
    for (size_t i = 0; i < static_cast<size_t>(bpp); ++i) out[i] = row[i];
    for (size_t i = bpp; i < bytes; ++i) out[i] = static_cast<unsigned char>(row[i] - row[i - bpp]);
    return;
  }
  for (size_t i = 0; i < bytes; ++i) {
    const int a = i >= static_cast<size_t>(bpp) ? row[i - bpp] : 0;
    const int b = up ? up[i] : 0;
    const int c = up && i >= static_cast<size_t>(bpp) ? up[i - bpp] : 0;
    out[i] = static_cast<unsigned char>(row[i] - paethPredictor(a, b, c));
  }
}

}  // namespace

std::vector<unsigned char> encodePng(const PngPixels& p, int level) {
  ACPCA_CHECK(p.width > 0 && p.height > 0 && p.channels >= 1 && p.channels <= 4 &&
                  (p.bitDepth == 8 || p.bitDepth == 16),
              "PNG of ", p.width, "x", p.height, "x", p.channels, " at ", p.bitDepth, " bits");
  const int bpp = p.channels * p.bitDepth / 8;
  const size_t rowBytes = static_cast<size_t>(p.width) * bpp;
  // Big-endian samples, rows in turn; 8-bit rows are read in place.
  thread_local std::vector<unsigned char> swapped;
  const auto* source = static_cast<const unsigned char*>(p.values);
  if (p.bitDepth == 16) {
    swapped.resize(rowBytes * p.height);
    const auto* v = static_cast<const std::uint16_t*>(p.values);
    for (size_t i = 0; i < swapped.size() / 2; ++i) {
      swapped[2 * i] = static_cast<unsigned char>(v[i] >> 8);
      swapped[2 * i + 1] = static_cast<unsigned char>(v[i]);
    }
    source = swapped.data();
  }
  const Filter filter = level <= 3 ? kSub : kPaeth;
  // Kept per thread from image to image: fresh pages cost the kernel's zeroing.
  thread_local std::vector<unsigned char> filtered, idat;
  filtered.resize((rowBytes + 1) * p.height);
  for (int y = 0; y < p.height; ++y) {
    unsigned char* out = &filtered[(rowBytes + 1) * y];
    const unsigned char* row = source + rowBytes * y;
    out[0] = filter;
    filterRow(filter, row, y > 0 ? row - rowBytes : nullptr, rowBytes, bpp, out + 1);
  }
  idat.clear();
  appendZlibStream(filtered.data(), filtered.size(), level, idat);

  // Colour types (PNG 11.2.2): grey 0, grey + alpha 4, RGB 2, RGBA 6.
  static constexpr unsigned char kColourType[5] = {0, 0, 4, 2, 6};
  std::vector<unsigned char> header;
  appendBigEndian(header, static_cast<std::uint32_t>(p.width));
  appendBigEndian(header, static_cast<std::uint32_t>(p.height));
  header.insert(header.end(), {static_cast<unsigned char>(p.bitDepth), kColourType[p.channels], 0,
                               0, 0});  // deflate, adaptive filtering, no interlace
  std::vector<unsigned char> file(kSignature, kSignature + 8);
  file.reserve(idat.size() + 64);
  appendChunk(file, "IHDR", header.data(), header.size());
  if (p.chunks)
    for (const PngChunk& chunk : *p.chunks)
      appendChunk(file, chunk.type.data(), chunk.data.data(), chunk.data.size());
  appendChunk(file, "IDAT", idat.data(), idat.size());
  appendChunk(file, "IEND", nullptr, 0);
  return file;
}

}  // namespace acpca
