#include "pipeline/tile_files.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/atomic_file.h"
#include "core/error.h"
#include "transport/hdf5_handles.h"

namespace acpca {

namespace fs = std::filesystem;

std::string buildWorkDirectory(const std::string& outPath) {
  return outPath + ".tiles";
}

std::string tilePath(const std::string& dir, size_t tile) {
  char name[32];
  std::snprintf(name, sizeof name, "tile-%07zu.h5", tile);
  return (fs::path(dir) / name).string();
}

std::uint64_t fingerprint(const void* data, size_t bytes, std::uint64_t hash) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
  return hash;
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(concat(path, ": cannot read"));
  std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw UserError(concat(path, ": cannot read"));
  return bytes;
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  AtomicOutput output(path);
  {
    std::ofstream out(output.tempPath(), std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw WriteError(concat(path, ": cannot write (disk full?)"));
  }
  output.commit();
}

std::vector<float> readTileArray(const std::string& path, const std::string& name, size_t size) {
  const h5::Handle file = h5::openFileReadOnly(path);
  if (h5::datasetShape(file.get(), name, path) != std::vector<hsize_t>{size})
    throw UserError(concat(path, ": dataset '", name, "' has the wrong size"));
  std::vector<float> values(size);
  h5::readDataset(file.get(), name, values.data(), path);
  return values;
}

void prepareWorkDirectory(const std::string& dir, const std::string& identity, bool resume,
                          const std::function<void(const std::string&)>& log) {
  const std::string stamp = (fs::path(dir) / "build.json").string();
  std::error_code ec;
  if (resume && fs::exists(stamp, ec)) {
    std::ifstream in(stamp);
    const std::string found((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (found != identity)
      throw UserError(concat(dir,
                             ": was left by a build of another scene or other settings; "
                             "build again without resuming to start over"));
    return;
  }
  if (fs::exists(dir, ec)) {
    if (log)
      log(concat("starting over: removing ", dir, resume ? "" : " (resuming would continue it)"));
    fs::remove_all(dir, ec);
    if (ec) throw WriteError(concat(dir, ": cannot remove (", ec.message(), ")"));
  }
  createOutputDirectory(dir);
  writeTextFile(stamp, identity);
}

}  // namespace acpca
