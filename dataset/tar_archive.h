#pragma once
// Tar files written through libarchive, the same bytes whenever the same
// files go in: members in the order given, each with a fixed mode, time
// (0), owner (0, no names) and the name given, so shards made again are
// byte-identical (docs/datasets.md, "Shards").
#include <string>
#include <vector>

namespace acpca {

/// A file to put in a tar: its name there, and where its bytes are now.
struct TarMember {
  std::string name;
  std::string source;
};

/// Writes `members` as a POSIX (ustar) tar at `path`, under a temporary
/// name renamed into place once whole. UserError naming the file that
/// cannot be read; WriteError naming `path` when the disk refuses it.
void writeTar(const std::string& path, const std::vector<TarMember>& members);

}  // namespace acpca
