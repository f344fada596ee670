#include "core/input_guard.h"

#include <sys/stat.h>

#include <filesystem>

#include "core/error.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileId& o) const { return device == o.device && inode == o.inode; }
};

/// The file a path leads to (links followed); false when there is none.
bool fileId(const std::string& path, FileId& id) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return false;
  id = {s.st_dev, s.st_ino};
  return true;
}

bool isSymbolicLink(const std::string& path) {
  struct stat s {};
  return ::lstat(path.c_str(), &s) == 0 && S_ISLNK(s.st_mode);
}

}  // namespace

void refuseOutputOverInputs(const std::string& output, const std::vector<std::string>& inputs) {
  FileId out;
  if (output.empty() || !fileId(output, out)) return;  // a new file replaces nothing
  for (const std::string& input : inputs) {
    FileId in;
    if (input.empty() || !fileId(input, in) || !(in == out)) continue;
    std::error_code ec;
    const bool samePath = fs::weakly_canonical(fs::absolute(output, ec), ec) ==
                          fs::weakly_canonical(fs::absolute(input, ec), ec);
    const std::string how = isSymbolicLink(output)  ? "is a symbolic link to the input"
                            : isSymbolicLink(input) ? "is the file that the input links to:"
                            : samePath              ? "is the input"
                                                    : "is a hard link of the input";
    throw UserError(concat("output ", output, " ", how, " ", input,
                           ": writing it would destroy the input; choose another output path"));
  }
}

void refuseDirectoryOverInputs(const std::string& outputDir,
                               const std::vector<std::string>& inputs) {
  FileId dir;
  if (outputDir.empty() || !fileId(outputDir, dir)) return;  // not there yet: holds nothing
  for (const std::string& input : inputs) {
    FileId in;
    if (input.empty() || !fileId(input, in)) continue;
    std::error_code ec;
    // The input itself (a directory of maps) and every directory above it.
    fs::path at = fs::weakly_canonical(fs::absolute(input, ec), ec);
    if (ec) continue;
    for (fs::path parent = at; !parent.empty(); parent = parent.parent_path()) {
      FileId above;
      if (fileId(parent.string(), above) && above == dir)
        throw UserError(concat("output directory ", outputDir, " holds the input ", input,
                               ": its outputs could replace the input; choose another output "
                               "directory"));
      if (parent == parent.root_path()) break;
    }
  }
}

}  // namespace acpca
