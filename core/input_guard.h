#pragma once
// A command never writes over what it reads: an output that is one of the
// inputs (the same path, a symbolic link to it or a hard link of it) or an
// output directory that holds one is refused before any work. Files are
// compared by device and inode, not by name.
#include <string>
#include <vector>

namespace acpca {

/// Throws UserError naming both when the file `output` is one of `inputs`.
/// Inputs that are no files (a built-in scene or lighting) are skipped.
void refuseOutputOverInputs(const std::string& output, const std::vector<std::string>& inputs);

/// Throws UserError naming both when the directory `outputDir` (which need not
/// exist yet) holds one of `inputs`, at any depth.
void refuseDirectoryOverInputs(const std::string& outputDir,
                               const std::vector<std::string>& inputs);

}  // namespace acpca
