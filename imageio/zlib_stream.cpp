#include "imageio/zlib_stream.h"

#include <isa-l/igzip_lib.h>
#include <libdeflate.h>

#include <algorithm>
#include <memory>

#include "core/error.h"

namespace acpca {

namespace {

/// libdeflate's compressors, one per level and thread: making one allocates
/// its hash tables, as long as compressing a small frame.
libdeflate_compressor& deflateCompressor(int level) {
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  thread_local std::unique_ptr<libdeflate_compressor, Free> compressors[10];
  auto& compressor = compressors[level];
  if (!compressor) compressor.reset(libdeflate_alloc_compressor(level));
  ACPCA_CHECK(compressor != nullptr, "libdeflate compressor of level ", level);
  return *compressor;
}

void appendByLibdeflate(const unsigned char* bytes, size_t size, int level,
                        std::vector<unsigned char>& out) {
  libdeflate_compressor& compressor = deflateCompressor(level);
  const size_t start = out.size();
  out.resize(start + libdeflate_zlib_compress_bound(&compressor, size));
  const size_t written =
      libdeflate_zlib_compress(&compressor, bytes, size, out.data() + start, out.size() - start);
  ACPCA_CHECK(written > 0, "libdeflate's bound of ", size, " bytes was too small");
  out.resize(start + written);
}

void appendByIsal(const unsigned char* bytes, size_t size, int level,
                  std::vector<unsigned char>& out) {
  static constexpr size_t kLevelBuffer[] = {ISAL_DEF_LVL0_DEFAULT, ISAL_DEF_LVL1_DEFAULT,
                                            ISAL_DEF_LVL2_DEFAULT, ISAL_DEF_LVL3_DEFAULT};
  thread_local std::vector<unsigned char> levelBuffer;
  levelBuffer.resize(kLevelBuffer[level]);
  // Stored blocks at worst, a few bytes per 64 KiB, plus the zlib frame.
  const size_t bound = size + size / 16 + 1024;
  const size_t start = out.size();
  out.resize(start + bound);
  isal_zstream stream;
  isal_deflate_stateless_init(&stream);
  stream.level = static_cast<uint32_t>(level);
  stream.level_buf = levelBuffer.data();
  stream.level_buf_size = static_cast<uint32_t>(levelBuffer.size());
  stream.gzip_flag = IGZIP_ZLIB;
  stream.end_of_stream = 1;
  stream.flush = NO_FLUSH;
  stream.next_in = const_cast<unsigned char*>(bytes);  // read only
  stream.avail_in = static_cast<uint32_t>(size);
  stream.next_out = out.data() + start;
  stream.avail_out = static_cast<uint32_t>(bound);
  const int status = isal_deflate_stateless(&stream);
  ACPCA_CHECK(status == COMP_OK, "igzip of ", size, " bytes at level ", level, ": ", status);
  out.resize(start + stream.total_out);
}

}  // namespace

void appendZlibStream(const unsigned char* bytes, size_t size, int level,
                      std::vector<unsigned char>& out) {
  level = std::clamp(level, 0, 9);
  ACPCA_CHECK(size < (size_t{1} << 31), "a zlib stream of ", size, " bytes");
  if (level >= 1 && level <= 3) return appendByIsal(bytes, size, level, out);
  appendByLibdeflate(bytes, size, level, out);
}

}  // namespace acpca
