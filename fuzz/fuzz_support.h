#pragma once
// Shared by the fuzz targets: the input written to a per-process file (the
// readers take paths), and the rule that only UserError may escape.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"

namespace acpca::fuzz {

/// This process's input file, in $TMPDIR (scripts/fuzz.sh gives each run a
/// directory it removes afterwards) or /tmp: acpca-fuzz-PID then `suffix`.
inline std::string inputPath(const std::string& suffix) {
  const char* folder = std::getenv("TMPDIR");
  std::string path = folder && *folder ? folder : "/tmp";
  path += "/acpca-fuzz-";
  path += std::to_string(::getpid());
  path += suffix;
  return path;
}

/// This process's input file holding `size` bytes of `data`, with the given extension.
inline std::string writeInput(const std::uint8_t* data, size_t size, const std::string& extension) {
  const std::string path = inputPath(extension);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs f; a UserError is the expected refusal of bad input, anything else
/// (another exception, a non-finite result reported by f) is a finding.
template <typename F>
int runReader(F&& f) {
  try {
    f();
  } catch (const UserError&) {
  }
  return 0;
}

/// Traps when any value is NaN or infinite: accepted input must give finite output.
inline void requireFinite(const std::vector<float>& values, const char* what) {
  for (float v : values)
    if (!std::isfinite(v)) {
      std::fprintf(stderr, "non-finite %s from accepted input\n", what);
      std::abort();
    }
}

}  // namespace acpca::fuzz
