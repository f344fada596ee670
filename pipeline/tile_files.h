#pragma once
// Where a streamed build keeps its finished tiles until it assembles the
// model (OUT.tiles/: one HDF5 file of clusters per tile, and build.json, what
// --resume checks), and the byte-level file helpers the ranks share.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace acpca {

/// Where a build of outPath keeps its finished tiles.
std::string buildWorkDirectory(const std::string& outPath);
/// The file of tile `tile` there.
std::string tilePath(const std::string& dir, size_t tile);
/// Starts the work directory over, or (resume) checks that it belongs to the
/// build of this identity: settings and fingerprints.
void prepareWorkDirectory(const std::string& dir, const std::string& identity, bool resume,
                          const std::function<void(const std::string&)>& log);
/// FNV-1a over bytes: a fingerprint of what a resumed build must share with
/// the build it continues (not a defence against tampering).
std::uint64_t fingerprint(const void* data, size_t bytes,
                          std::uint64_t hash = 14695981039346656037ull);
/// A file's bytes, and a file written from bytes atomically.
std::vector<char> readBytes(const std::string& path);
void writeBytes(const std::string& path, const std::vector<char>& bytes);
/// A float dataset of a tile file, of the size expected.
std::vector<float> readTileArray(const std::string& path, const std::string& name, size_t size);

}  // namespace acpca
