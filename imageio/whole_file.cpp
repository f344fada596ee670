#include "imageio/whole_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace acpca {

bool writeWholeFile(const std::string& file, const void* bytes, size_t size, std::string& error) {
  std::FILE* out = std::fopen(file.c_str(), "wb");
  if (!out) return error = std::strerror(errno), false;
  const bool written = std::fwrite(bytes, 1, size, out) == size;
  const int writeErrno = errno;
  if (std::fclose(out) != 0 || !written) {
    error = std::strerror(written ? errno : writeErrno);
    std::remove(file.c_str());
    return false;
  }
  return true;
}

}  // namespace acpca
