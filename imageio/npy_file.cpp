#include "imageio/npy_file.h"

#include <bit>
#include <fstream>

#include "core/error.h"

namespace acpca {

namespace {

static_assert(std::endian::native == std::endian::little, "npy values are written as stored");

void writeNpyBytes(const std::string& file, const std::string& path, const char* descr,
                   const std::vector<size_t>& shape, const void* values, size_t valueBytes) {
  std::string dims;
  size_t count = 1;
  for (size_t d : shape) {
    dims += std::to_string(d) + ", ";
    count *= d;
  }
  if (shape.size() > 1)
    dims.erase(dims.size() - 2);  // "(H, W)" but "(N,)"
  else if (!shape.empty())
    dims.erase(dims.size() - 1);
  std::string header =
      concat("{'descr': '", descr, "', 'fortran_order': False, 'shape': (", dims, "), }");
  // Magic (6), version (2) and length (2) before it; the whole is padded with
  // spaces to a multiple of 64 bytes and ends in a newline.
  const size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  const char magic[8] = {'\x93', 'N', 'U', 'M', 'P', 'Y', 1, 0};
  const std::uint16_t length = static_cast<std::uint16_t>(header.size());
  out.write(magic, 8);
  out.write(reinterpret_cast<const char*>(&length), 2);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(static_cast<const char*>(values), static_cast<std::streamsize>(count * valueBytes));
  out.close();
  if (!out) throw WriteError(concat(path, ": cannot write the array (disk full?)"));
}

}  // namespace

void writeNpy(const std::string& file, const std::string& path, const std::vector<size_t>& shape,
              const float* values) {
  writeNpyBytes(file, path, "<f4", shape, values, sizeof(float));
}

void writeNpy(const std::string& file, const std::string& path, const std::vector<size_t>& shape,
              const std::int32_t* values) {
  writeNpyBytes(file, path, "<i4", shape, values, sizeof(std::int32_t));
}

}  // namespace acpca
